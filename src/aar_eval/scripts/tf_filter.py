#!/usr/bin/env python3
"""Relays ~input (default /tf_recorded) to ~output (default /tf) without the transforms whose
child frame is in ~drop_child_frames (default [receiver]): a replayed flight keeps the
simulator's truth and the boom's links, but not the live run's estimates, which the replay
makes anew."""
import rospy
from tf2_msgs.msg import TFMessage


def main():
    rospy.init_node("tf_filter")
    drop = set(rospy.get_param("~drop_child_frames", ["receiver"]))
    pub = rospy.Publisher(rospy.get_param("~output", "/tf"), TFMessage, queue_size=100)

    def relay(msg):
        kept = [t for t in msg.transforms if t.child_frame_id not in drop]
        if kept:
            pub.publish(TFMessage(transforms=kept))

    rospy.Subscriber(rospy.get_param("~input", "/tf_recorded"), TFMessage, relay, queue_size=100)
    rospy.spin()


if __name__ == "__main__":
    main()
