#!/usr/bin/env python3
"""Per-frame wall-clock arrival times for scripts/bench-realtime: when each frame's left camera info
arrives from the bag player (the images leave with it), when its cloud leaves stereo
(/stereo/points2) and occlusion (/aar/points_filtered, and the boom's points /aar/boom_points),
and when its aar/pose_estimate is published. Appends to ~output (CSV) as they come:
  kind,stamp_ns,wall_s,valid,registration_ms,track,points
kind is frame, cloud, filtered, boom or estimate; wall_s is time.monotonic() (one clock for all);
points is a cloud's point count."""
import struct
import time

import rospy
from aar_msgs.msg import PoseEstimate
from sensor_msgs.msg import CameraInfo


def main():
    rospy.init_node("realtime_probe")
    out = open(rospy.get_param("~output"), "w", buffering=1)
    out.write("kind,stamp_ns,wall_s,valid,registration_ms,track,points\n")

    def on_frame(msg):
        out.write(f"frame,{msg.header.stamp.to_nsec()},{time.monotonic():.6f},,,,\n")

    def on_cloud(kind):
        # Raw bytes, not deserialised: the stamp is at bytes 4-12 (header seq, secs, nsecs), then
        # the frame id (length, characters), height and width; the probe should cost the machine
        # it measures as little as it can.
        def write(msg):
            now = time.monotonic()
            secs, nsecs, id_length = struct.unpack_from("<III", msg._buff, 4)
            height, width = struct.unpack_from("<II", msg._buff, 16 + id_length)
            out.write(f"{kind},{secs * 1000000000 + nsecs},{now:.6f},,,,{height * width}\n")
        return write

    def on_estimate(msg):
        now = time.monotonic()
        out.write(f"estimate,{msg.header.stamp.to_nsec()},{now:.6f},{int(msg.valid)},"
                  f"{msg.registration_ms:.3f},{msg.track},\n")

    # tcp_nodelay: no Nagle delay on small messages, which would add to the latency measured.
    rospy.Subscriber("/stereo/left/camera_info", CameraInfo, on_frame, queue_size=100,
                     tcp_nodelay=True)
    # ~stage_times false: no cloud subscriptions, to see what listening to them costs.
    if rospy.get_param("~stage_times", True):
        rospy.Subscriber("/stereo/points2", rospy.AnyMsg, on_cloud("cloud"), queue_size=100,
                         tcp_nodelay=True)
        rospy.Subscriber("/aar/points_filtered", rospy.AnyMsg, on_cloud("filtered"),
                         queue_size=100, tcp_nodelay=True)
        rospy.Subscriber("/aar/boom_points", rospy.AnyMsg, on_cloud("boom"), queue_size=100,
                         tcp_nodelay=True)
    rospy.Subscriber("/aar/pose_estimate", PoseEstimate, on_estimate, queue_size=100,
                     tcp_nodelay=True)
    rospy.spin()
    out.close()


if __name__ == "__main__":
    main()
