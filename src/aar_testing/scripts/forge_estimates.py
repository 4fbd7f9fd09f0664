#!/usr/bin/env python3
"""A forger on a run's own master (the tests' fail-fast case): for each frame (its left camera
info) it publishes an estimate 1 km off at that stamp on /aar/pose_estimate, writing CALLERID
(the registration's, /aar_manager) into its connection header, as rospy lets any node do. Ends
after SECONDS, or when the master has gone (the run ended).
  forge_estimates.py CALLERID SECONDS   (ROS_MASTER_URI: the run's master)"""
import sys
import time

import rosgraph
import rospy
from aar_msgs.msg import PoseEstimate
from sensor_msgs.msg import CameraInfo


def main():
    caller, seconds = sys.argv[1], float(sys.argv[2])
    rospy.init_node("forger", anonymous=True, disable_signals=True)
    pub = rospy.Publisher("/aar/pose_estimate", PoseEstimate, queue_size=10,
                          headers={"callerid": caller})
    sent = [0]

    def forge(info):
        m = PoseEstimate(valid=True)
        m.header.stamp = info.header.stamp
        m.header.frame_id = "tanker"
        m.pose.position.x = 1000.0
        m.pose.orientation.w = 1.0
        pub.publish(m)
        sent[0] += 1
    rospy.Subscriber("/stereo/left/camera_info", CameraInfo, forge, queue_size=10)
    master = rosgraph.Master("/forger")
    end = time.monotonic() + seconds
    while time.monotonic() < end and master.is_online():
        time.sleep(0.5)
    print(f"forger: {sent[0]} estimates sent as {caller}", flush=True)
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
