#include "aar_eval/ros/conversions.h"

#include <tf2_eigen/tf2_eigen.h>

namespace aar_eval {

Estimate ToEstimate(const aar_msgs::PoseEstimate& msg) {
  Estimate e;
  e.valid = msg.valid;
  tf2::fromMsg(msg.pose, e.T_tanker_receiver);
  e.converged = msg.converged;
  e.iterations = static_cast<int>(msg.iterations);
  e.rms = msg.rms;
  e.registration_ms = msg.registration_ms;
  for (int i = 0; i < 36; ++i) e.covariance(i / 6, i % 6) = msg.covariance[i];
  static const char* const kTrack[] = {"off",    "started", "accepted", "rejected",
                                       "missed", "lost",    "reset"};  // TRACK_* in order
  e.track = msg.track < sizeof(kTrack) / sizeof(kTrack[0]) ? kTrack[msg.track] : "?";
  e.alert = msg.integrity == aar_msgs::PoseEstimate::INTEGRITY_ALERT;
  e.protection_level_position = msg.protection_level_position;
  e.protection_level_attitude = msg.protection_level_attitude;
  e.alert_limit_position = msg.alert_limit_position;
  e.alert_limit_attitude = msg.alert_limit_attitude;
  return e;
}

aar_msgs::PoseError ToPoseErrorMsg(const FrameRecord& f, const std_msgs::Header& header) {
  aar_msgs::PoseError msg;
  msg.header = header;
  msg.region = static_cast<uint8_t>(f.region);
  msg.range_m = f.range_m;
  msg.x_m = f.error[0], msg.y_m = f.error[1], msg.z_m = f.error[2];
  msg.roll_deg = f.error[3], msg.pitch_deg = f.error[4], msg.yaw_deg = f.error[5];
  return msg;
}

}  // namespace aar_eval
