#!/usr/bin/env python3
"""Plays a recorded flight over and over with time going forward, for scripts/soak.

rosbag play --loop would send time backwards at every loop: tf buffers clear and the tracker
resets on old stamps. This node reads the bag once into memory and publishes it frame by frame
for ~frames frames; loop L shifts every header stamp, tf stamp and /clock by L times the bag's
length (last frame - first frame + one frame period), so stamps increase across loops.

Per frame: /clock (the frame's stamp, held until the next frame, as the simulator does in
lockstep), the bag's /tf of that stamp (truth and the boom's links; the live run's `receiver`
estimates are dropped, the graph makes its own), /joint_states, both camera infos and images.
The recorded /aar/pose_estimate is not played. The bag's /tf_static messages are merged and
published once, latched.

Paced by the graph: frame k+1 goes out when frame k's /aar/pose_estimate (valid or not) came,
or after ~estimate_timeout wall seconds (~first_timeout for the first frame, while the graph
starts), so that a stalled graph shows as missing estimates instead of being waited for.

~status (a file) is rewritten after every frame and estimate, one JSON object:
  frames (published), estimates (received), valid (with a pose), timeouts, first_frame_wall,
  last_valid_wall (time.monotonic(), one clock for every process), done (all frames published
  and the last one answered or timed out).
Fault injection for the soak's own test: ~leak_kb_per_frame keeps that much memory per frame."""
import json
import os
import threading
import time

import rosbag
import rospy
from aar_msgs.msg import PoseEstimate
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, JointState
from tf2_msgs.msg import TFMessage

FRAME_TOPICS = {
    "/stereo/left/image_rect": Image,
    "/stereo/right/image_rect": Image,
    "/stereo/left/camera_info": CameraInfo,
    "/stereo/right/camera_info": CameraInfo,
    "/joint_states": JointState,
}


def load(path, drop_children):
    """The bag as frames in stamp order: [(stamp, [(topic, msg), ...])], the merged static tf
    and the frame period [s]. A frame is the left camera info's stamp; every other message goes
    with the frame of its stamp (the newest frame not after it)."""
    static = {}
    stamped = []  # (stamp, topic, msg)
    with rosbag.Bag(path) as bag:
        for topic, msg, _ in bag.read_messages():
            if topic == "/tf_static":
                for t in msg.transforms:
                    static[t.child_frame_id] = t
            elif topic == "/tf":
                kept = [t for t in msg.transforms if t.child_frame_id not in drop_children]
                if kept:
                    stamped.append((kept[0].header.stamp, topic, TFMessage(transforms=kept)))
            elif topic in FRAME_TOPICS:
                stamped.append((msg.header.stamp, topic, msg))
    stamps = sorted({s for s, topic, _ in stamped if topic == "/stereo/left/camera_info"})
    if len(stamps) < 2:
        raise RuntimeError(f"{path}: {len(stamps)} frames (left camera infos); a loop needs 2")
    frames = {s: [] for s in stamps}
    for s, topic, msg in stamped:
        owner = max((f for f in stamps if f <= s), default=stamps[0])
        frames[owner].append((topic, msg))
    for s in stamps:
        topics = {topic for topic, _ in frames[s]}
        missing = [t for t in FRAME_TOPICS if t not in topics and t != "/joint_states"]
        if missing:
            raise RuntimeError(
                f"{path}: the frame at {s.to_sec():.3f} s lacks {', '.join(missing)}")
    gaps = sorted((b - a).to_sec() for a, b in zip(stamps, stamps[1:]))
    period = gaps[len(gaps) // 2]
    if period <= 0.0:
        raise RuntimeError(f"{path}: two frames share a stamp")
    # Publish order within a frame: tf and joints first, so that the images' tf is there.
    order = {"/tf": 0, "/joint_states": 1}
    return ([(s, sorted(frames[s], key=lambda m: order.get(m[0], 2))) for s in stamps],
            list(static.values()), period)


def shift(topic, msg, offset):
    if topic == "/tf":
        for t in msg.transforms:
            t.header.stamp = t.header.stamp + offset
    else:
        msg.header.stamp = msg.header.stamp + offset


def main():
    rospy.init_node("soak_player")
    path = rospy.get_param("~bag")
    total = int(rospy.get_param("~frames"))
    timeout = float(rospy.get_param("~estimate_timeout", 10.0))
    first_timeout = float(rospy.get_param("~first_timeout", 120.0))
    status_path = rospy.get_param("~status", "")
    leak_kb = int(rospy.get_param("~leak_kb_per_frame", 0))
    drop = set(rospy.get_param("~drop_child_frames", ["receiver"]))
    if total < 1 or timeout <= 0.0 or leak_kb < 0:
        rospy.logfatal("soak_player: ~frames must be >= 1, ~estimate_timeout > 0 and "
                       "~leak_kb_per_frame >= 0 (frames %s, timeout %s, leak %s)",
                       total, timeout, leak_kb)
        raise SystemExit(1)
    frames, static, period = load(path, drop)
    length = (frames[-1][0] - frames[0][0]).to_sec() + period
    rospy.loginfo("soak_player: %d frames of %s, %.3f s a loop; playing %d frames",
                  len(frames), path, length, total)

    pubs = {t: rospy.Publisher(t, cls, queue_size=10) for t, cls in FRAME_TOPICS.items()}
    pubs["/tf"] = rospy.Publisher("/tf", TFMessage, queue_size=100)
    clock_pub = rospy.Publisher("/clock", Clock, queue_size=10)
    static_pub = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)

    cond = threading.Condition()
    state = {"frames": 0, "estimates": 0, "valid": 0, "timeouts": 0, "first_frame_wall": None,
             "last_valid_wall": None, "done": False}
    newest = {"stamp": rospy.Time(0)}

    def write_status():  # under cond
        if not status_path:
            return
        tmp = status_path + ".tmp"
        with open(tmp, "w") as f:
            json.dump(state, f)
        os.replace(tmp, status_path)

    def on_estimate(msg):
        with cond:
            state["estimates"] += 1
            if msg.valid:
                state["valid"] += 1
                state["last_valid_wall"] = time.monotonic()
            if msg.header.stamp > newest["stamp"]:
                newest["stamp"] = msg.header.stamp
            write_status()
            cond.notify_all()

    rospy.Subscriber("/aar/pose_estimate", PoseEstimate, on_estimate, queue_size=100)

    # The graph is up when stereo listens to both images; the static tf goes out first.
    clock_pub.publish(Clock(clock=frames[0][0]))
    static_pub.publish(TFMessage(transforms=static))
    images = [pubs["/stereo/left/image_rect"], pubs["/stereo/right/image_rect"]]
    while not rospy.is_shutdown() and any(p.get_num_connections() == 0 for p in images):
        time.sleep(0.05)
    time.sleep(2.0)  # the subscribers' other connections (tf, camera infos) settle

    leaked = []
    for k in range(total):
        if rospy.is_shutdown():
            return
        loop, index = divmod(k, len(frames))
        stamp, messages = frames[index]
        offset = rospy.Duration.from_sec(loop * length)
        frame_stamp = stamp + offset
        clock_pub.publish(Clock(clock=frame_stamp))
        for topic, msg in messages:
            shift(topic, msg, offset)
            pubs[topic].publish(msg)
            shift(topic, msg, -offset)  # the bag in memory stays as recorded
        if leak_kb:
            leaked.append(bytearray(os.urandom(leak_kb * 1024)))
        with cond:
            state["frames"] = k + 1
            if state["first_frame_wall"] is None:
                state["first_frame_wall"] = time.monotonic()
            write_status()
            limit = first_timeout if k == 0 else timeout
            if not cond.wait_for(lambda: rospy.is_shutdown() or newest["stamp"] >= frame_stamp,
                                 limit):
                state["timeouts"] += 1
                rospy.logwarn("soak_player: no pose estimate for frame %d (stamp %.3f) within "
                              "%.1f s; going on", k, frame_stamp.to_sec(), limit)
        if (k + 1) % 500 == 0:
            rospy.loginfo("soak_player: %d of %d frames, %d estimates (%d with a pose), "
                          "%d timeouts", k + 1, total, state["estimates"], state["valid"],
                          state["timeouts"])
    with cond:
        state["done"] = True
        write_status()
    rospy.loginfo("soak_player: done, %d frames, %d estimates (%d with a pose), %d timeouts",
                  total, state["estimates"], state["valid"], state["timeouts"])
    rospy.spin()  # stays until the soak stops the graph


if __name__ == "__main__":
    main()
