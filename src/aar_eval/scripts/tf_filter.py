#!/usr/bin/env python3
"""Relays ~input (default /tf_recorded; "": none) to ~output (default /tf) without the transforms
whose child frame is in ~drop_child_frames (default [receiver]): a replayed flight keeps the
simulator's truth and the boom's links, but not the live run's estimates, which the replay
makes anew.

It also merges ~static_input (default: none) into one latched ~static_output (default
/tf_static): a bag holds one /tf_static message per static publisher, and a player latches only
the last, so a node started late (respawned, rviz) would miss the others' frames.

Fault injection: with ~outage_start (s of bag time, >= 0) and ~outage_duration (s), nothing is
relayed in [start, start + duration): tf stops, then returns (scripts/replay --tf-outage)."""
import math

import rospy
from tf2_msgs.msg import TFMessage


def main():
    rospy.init_node("tf_filter")
    drop = set(rospy.get_param("~drop_child_frames", ["receiver"]))
    start = float(rospy.get_param("~outage_start", -1.0))
    duration = float(rospy.get_param("~outage_duration", 0.0))
    if not (math.isfinite(start) and math.isfinite(duration) and duration >= 0.0):
        rospy.logfatal("tf_filter: ~outage_start and ~outage_duration must be finite, the "
                       "duration >= 0 (start %s, duration %s)", start, duration)
        raise SystemExit(1)
    source = rospy.get_param("~input", "/tf_recorded")  # "": relay no /tf, only merge static
    pub = rospy.Publisher(rospy.get_param("~output", "/tf"), TFMessage, queue_size=100) \
        if source else None
    state = {"in_outage": False}

    def relay(msg):
        if start >= 0.0 and duration > 0.0:
            now = rospy.Time.now().to_sec()
            inside = start <= now < start + duration
            if inside != state["in_outage"]:
                state["in_outage"] = inside
                rospy.logwarn("tf_filter: tf outage %s at %.3f s (injected)",
                              "starts" if inside else "ends", now)
            if inside:
                return
        kept = [t for t in msg.transforms if t.child_frame_id not in drop]
        if kept:
            pub.publish(TFMessage(transforms=kept))

    if source:
        rospy.Subscriber(source, TFMessage, relay, queue_size=100)

    static_input = rospy.get_param("~static_input", "")
    if static_input:
        static_pub = rospy.Publisher(rospy.get_param("~static_output", "/tf_static"), TFMessage,
                                     queue_size=1, latch=True)
        merged = {}  # child frame -> its transform

        def merge(msg):
            for t in msg.transforms:
                merged[t.child_frame_id] = t
            static_pub.publish(TFMessage(transforms=list(merged.values())))

        rospy.Subscriber(static_input, TFMessage, merge, queue_size=100)
    rospy.spin()


if __name__ == "__main__":
    main()
