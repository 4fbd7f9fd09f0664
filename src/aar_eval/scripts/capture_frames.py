#!/usr/bin/env python3
"""Screenshots of the X display (rviz under Xvfb) at chosen frames: after the k-th pose estimate
(1-based, in arrival order) it waits ~delay seconds (wall; less than a frame's period at the
replay's rate) for rviz to draw, grabs the screen and writes ~output_dir/frame_KKK.png; it exits
once the last is written, on shutdown, or after ~timeout."""
import os
import sys
import threading

import rospy
from aar_msgs.msg import PoseEstimate
from PIL import ImageGrab


def main():
    rospy.init_node("capture_frames")
    frames = sorted(int(f) for f in str(rospy.get_param("~frames", "10")).split(",") if f.strip())
    out = rospy.get_param("~output_dir")
    delay = float(rospy.get_param("~delay", 0.6))
    timeout = float(rospy.get_param("~timeout", 300.0))
    display = os.environ.get("DISPLAY")
    if not display:
        rospy.logfatal("capture_frames: no DISPLAY (run rviz under Xvfb: scripts/capture)")
        sys.exit(1)
    os.makedirs(out, exist_ok=True)
    count = [0]
    pending = list(frames)
    done = threading.Event()
    failed = []

    def grab(k):
        path = os.path.join(out, f"frame_{k:03d}.png")
        try:
            ImageGrab.grab(xdisplay=display).save(path)
        except OSError as e:  # a full disk: no truncated PNG left behind, and no wait for it
            rospy.logfatal(f"capture_frames: cannot write {path}: {e}")
            if os.path.exists(path):
                os.remove(path)
            failed.append(path)
            done.set()
            return
        rospy.loginfo(f"capture_frames: wrote {path}")
        if k == frames[-1]:
            done.set()

    def on_estimate(_):
        count[0] += 1
        if pending and count[0] == pending[0]:
            k = pending.pop(0)
            threading.Timer(delay, grab, args=(k,)).start()

    rospy.Subscriber("/aar/pose_estimate", PoseEstimate, on_estimate, queue_size=50)
    waited = 0.0
    while not done.wait(0.2):
        waited += 0.2
        if rospy.is_shutdown() or waited > timeout:
            rospy.logerr(f"capture_frames: {count[0]} estimates; frames {pending} not captured")
            sys.exit(1)
    if failed:
        sys.exit(1)
    rospy.sleep(0.5)


if __name__ == "__main__":
    main()
