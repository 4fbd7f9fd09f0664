"""The bag a replay plays through the graph (scripts/replay, scripts/capture): readable, and
holding what the graph needs, and its rigs; and the messages on a topic of a bag
(scripts/bench-realtime)."""
import re
import subprocess
import sys

from campaign import workspace


def topic_messages(info, topic):
    """Messages on TOPIC in `rosbag info --yaml` output, 0 if absent."""
    on = False
    for line in info.splitlines():
        w = line.split()
        if len(w) >= 3 and w[0] == "-" and w[1] == "topic:":
            on = w[2] == topic
        elif on and len(w) >= 2 and w[0] == "messages:":
            return int(w[1]) if w[1].isdigit() else 0
    return 0


def read(bag):
    """`rosbag info --yaml` of BAG; exits 2 naming a broken (truncated, unindexed) bag."""
    prog = workspace.PROG
    r = subprocess.run(["timeout", "60", "rosbag", "info", "--yaml", bag],
                       env=workspace.ros_env(), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if r.returncode:
        last = ([line for line in r.stdout.splitlines() if line.strip()] or [""])[-1]
        print(f"{prog}: bag '{bag}' is broken: {last}", file=sys.stderr)
        print(f"{prog}: (a truncated or unfinished bag may be repaired with: rosbag reindex "
              f"'{bag}')", file=sys.stderr)
        sys.exit(2)
    return r.stdout


def rigs_of(info):
    """The stereo rigs whose left images the bag holds (/R/left/image_rect or image_raw; issue
    44), stereo first: pipeline.launch record:=FILE rigs:=stereo,R records each."""
    found = []
    for line in info.splitlines():
        w = line.split()
        m = re.fullmatch(r"/(\w+)/left/(image_rect|image_raw)", w[2]) \
            if len(w) >= 3 and w[0] == "-" and w[1] == "topic:" else None
        if m and m.group(1) not in found and topic_messages(info, w[2]) > 0:
            found.append(m.group(1))
    return sorted(found, key=lambda r: r != "stereo")


def check(bag, rigs=("stereo",), info=None):
    """(images, rectify, frames): images image_rect, or image_raw for a rig's raw images
    (rectify then true), and the left images' count. Exits 2 naming what is wrong: a broken bag,
    or one without what the graph needs (each of RIGS' images and camera infos)."""
    prog = workspace.PROG
    info = info if info is not None else read(bag)
    # Rectified images (the simulator's), or raw ones (a rig's, or pipeline.launch
    # rectify:=true).
    images, rectify = "image_rect", False
    if topic_messages(info, "/stereo/left/image_rect") == 0 and \
            topic_messages(info, "/stereo/left/image_raw") > 0:
        images, rectify = "image_raw", True
    needed = [f"/{r}/{side}/{kind}" for r in rigs for kind in (images, "camera_info")
              for side in ("left", "right")]
    missing = [t for t in needed + ["/tf_static", "/tf"] if topic_messages(info, t) <= 0]
    if missing:
        print(f"{prog}: bag '{bag}' lacks {' '.join(missing)}: stereo needs both images "
              "(image_rect, or image_raw to rectify) and camera infos, occlusion and eval the tf "
              "(/tf_static, /tf) that pipeline.launch record:=FILE writes", file=sys.stderr)
        sys.exit(2)
    return images, rectify, topic_messages(info, f"/stereo/left/{images}")
