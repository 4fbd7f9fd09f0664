"""The bag a replay plays through the graph (scripts/replay, scripts/capture): readable, and
holding what the graph needs; and the messages on a topic of a bag (scripts/bench-realtime)."""
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


def check(bag):
    """(images, rectify, frames): images image_rect, or image_raw for a rig's raw images
    (rectify then true), and the left images' count. Exits 2 naming what is wrong: a broken bag,
    or one without what the graph needs."""
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
    info = r.stdout
    # Rectified images (the simulator's), or raw ones (a rig's, or pipeline.launch
    # rectify:=true).
    images, rectify = "image_rect", False
    if topic_messages(info, "/stereo/left/image_rect") == 0 and \
            topic_messages(info, "/stereo/left/image_raw") > 0:
        images, rectify = "image_raw", True
    missing = [t for t in (f"/stereo/left/{images}", f"/stereo/right/{images}",
                           "/stereo/left/camera_info", "/stereo/right/camera_info", "/tf_static",
                           "/tf") if topic_messages(info, t) <= 0]
    if missing:
        print(f"{prog}: bag '{bag}' lacks {' '.join(missing)}: stereo needs both images "
              "(image_rect, or image_raw to rectify) and camera infos, occlusion and eval the tf "
              "(/tf_static, /tf) that pipeline.launch record:=FILE writes", file=sys.stderr)
        sys.exit(2)
    return images, rectify, topic_messages(info, f"/stereo/left/{images}")
