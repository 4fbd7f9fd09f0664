#!/usr/bin/env python3
"""Writes every /aar/pose_estimate to ~output (CSV, one row a frame, flushed per row): the record
of a flight without truth (a rig's bag, scripts/replay --no-truth), where eval has nothing to
score. Columns: stamp [s], valid, x_m, y_m, z_m (T_tanker_receiver's translation in the tanker
frame), roll_deg, pitch_deg, yaw_deg (intrinsic z-y'-x''), range_m (distance from the tanker
origin), track (PoseEstimate's TRACK_* value), fitness, rms_m, sensed_points, total_ms."""
import csv
import math
import os
import sys

import rospy
from aar_msgs.msg import PoseEstimate

COLUMNS = ["stamp", "valid", "x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg", "range_m",
           "track", "fitness", "rms_m", "sensed_points", "total_ms"]


def euler_zyx_deg(q):
    """Roll, pitch, yaw [deg] of a unit quaternion, intrinsic z-y'-x'' (the flight-path CSV's)."""
    w, x, y, z = q.w, q.x, q.y, q.z
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return [math.degrees(a) for a in (roll, pitch, yaw)]


def main():
    rospy.init_node("estimates_csv")
    path = rospy.get_param("~output", "")
    if not path:
        rospy.logfatal("estimates_csv: ~output (the CSV to write) is not set")
        sys.exit(1)
    try:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        out = open(path, "w", newline="")
    except OSError as e:
        rospy.logfatal("estimates_csv: cannot write '%s': %s", path, e)
        sys.exit(1)
    writer = csv.writer(out)
    writer.writerow(COLUMNS)
    out.flush()

    def on_estimate(msg):
        p = msg.pose.position
        row = [f"{msg.header.stamp.to_sec():.6f}", int(msg.valid)]
        if msg.valid:
            row += [f"{v:.4f}" for v in (p.x, p.y, p.z)]
            row += [f"{v:.3f}" for v in euler_zyx_deg(msg.pose.orientation)]
            row.append(f"{math.sqrt(p.x * p.x + p.y * p.y + p.z * p.z):.3f}")
        else:
            row += [""] * 7
        row += [msg.track, f"{msg.fitness:.4f}", f"{msg.rms:.4f}", msg.sensed_points,
                f"{msg.total_ms:.1f}"]
        writer.writerow(row)
        out.flush()

    rospy.Subscriber("/aar/pose_estimate", PoseEstimate, on_estimate, queue_size=100)
    rospy.spin()
    out.close()


if __name__ == "__main__":
    main()
