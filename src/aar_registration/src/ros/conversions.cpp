#include "aar_registration/ros/conversions.h"

#include <array>
#include <set>

#include <aar_ros_common/point_cloud.h>
#include <tf2_eigen/tf2_eigen.h>

namespace aar_registration {

ReferencePoints ToReferencePoints(const sensor_msgs::PointCloud2& msg) {
  const aar_ros_common::CloudPoints cloud = aar_ros_common::FromCloud(msg);
  std::vector<uint32_t> keep;  // positions in cloud.points
  if (aar_ros_common::HasField(msg, "visibility")) {
    const std::vector<double> classes = aar_ros_common::ReadField(msg, "visibility", cloud.indices);
    for (size_t i = 0; i < classes.size(); ++i) {
      if (classes[i] == 0.0) keep.push_back(static_cast<uint32_t>(i));
    }
  } else {
    for (uint32_t i = 0; i < cloud.points.size(); ++i) keep.push_back(i);
  }
  ReferencePoints out;
  for (const uint32_t i : keep) out.points.push_back(cloud.points[i]);
  if (aar_ros_common::HasField(msg, "normal_x")) {
    std::vector<uint32_t> at;
    for (const uint32_t i : keep) at.push_back(cloud.indices[i]);
    const auto nx = aar_ros_common::ReadField(msg, "normal_x", at),
               ny = aar_ros_common::ReadField(msg, "normal_y", at),
               nz = aar_ros_common::ReadField(msg, "normal_z", at);
    for (size_t i = 0; i < at.size(); ++i) out.normals.emplace_back(nx[i], ny[i], nz[i]);
  }
  return out;
}

ReferencePoints MergeReferences(std::vector<ReferencePoints> rigs) {
  if (rigs.empty()) return {};
  // Normals when every rig with points gives them.
  bool normals = true;
  for (const ReferencePoints& rig : rigs)
    normals = normals && (rig.points.empty() || rig.normals.size() == rig.points.size());
  ReferencePoints out = std::move(rigs.front());
  if (!normals) out.normals.clear();
  auto key = [](const Eigen::Vector3d& p) { return std::array<double, 3>{p.x(), p.y(), p.z()}; };
  std::set<std::array<double, 3>> seen;
  for (const Eigen::Vector3d& p : out.points) seen.insert(key(p));
  for (size_t r = 1; r < rigs.size(); ++r) {
    const ReferencePoints& rig = rigs[r];
    for (size_t i = 0; i < rig.points.size(); ++i) {
      if (!seen.insert(key(rig.points[i])).second) continue;
      out.points.push_back(rig.points[i]);
      if (normals) out.normals.push_back(rig.normals[i]);
    }
  }
  return out;
}

// The message's constants follow the enums' order.
static_assert(aar_msgs::PoseEstimate::SEED_CENTROID == static_cast<int>(SeedMode::kCentroid) &&
              aar_msgs::PoseEstimate::SEED_PREVIOUS == static_cast<int>(SeedMode::kPrevious) &&
              aar_msgs::PoseEstimate::SEED_PREDICTION == static_cast<int>(SeedMode::kPrediction));
static_assert(
    aar_msgs::PoseEstimate::TRACK_STARTED == 1 + static_cast<int>(TrackOutcome::kStarted) &&
    aar_msgs::PoseEstimate::TRACK_ACCEPTED == 1 + static_cast<int>(TrackOutcome::kAccepted) &&
    aar_msgs::PoseEstimate::TRACK_REJECTED == 1 + static_cast<int>(TrackOutcome::kRejected) &&
    aar_msgs::PoseEstimate::TRACK_MISSED == 1 + static_cast<int>(TrackOutcome::kMissed) &&
    aar_msgs::PoseEstimate::TRACK_LOST == 1 + static_cast<int>(TrackOutcome::kLost) &&
    aar_msgs::PoseEstimate::TRACK_RESET == 1 + static_cast<int>(TrackOutcome::kReset));

aar_msgs::PoseEstimate ToPoseEstimate(const RegistrarResult& r, const std_msgs::Header& header,
                                      double total_ms) {
  aar_msgs::PoseEstimate estimate;  // valid = false: a miss, and lockstep moves on
  estimate.header = header;
  estimate.total_ms = total_ms;
  estimate.seed = static_cast<uint8_t>(r.seed);  // SEED_* in SeedMode's order
  // TRACK_* is 0 for off, then TrackOutcome's order.
  estimate.track = static_cast<uint8_t>(r.tracking ? 1 + static_cast<int>(r.track.outcome)
                                                   : aar_msgs::PoseEstimate::TRACK_OFF);
  estimate.track_reason = r.tracking ? r.track.reason : "";
  // The outline's decision (a start refused, a maneuver, an integrity loss, not fused) with it.
  if (!r.outline_note.empty() && estimate.track_reason.find(r.outline_note) == std::string::npos)
    estimate.track_reason += (estimate.track_reason.empty() ? "" : "; ") + r.outline_note;
  estimate.mahalanobis2 = r.track.mahalanobis2;
  estimate.registered = r.registered;
  estimate.registered_pose = tf2::toMsg(r.T_tanker_receiver_registered);
  estimate.integrity = r.integrity.alert ? aar_msgs::PoseEstimate::INTEGRITY_ALERT
                                         : aar_msgs::PoseEstimate::INTEGRITY_OK;
  estimate.integrity_reason = r.integrity.reason;
  if (!r.valid) {
    estimate.pose.orientation.w = 1.0;
    return estimate;
  }
  estimate.valid = true;
  estimate.pose = tf2::toMsg(r.T_tanker_receiver);
  for (int i = 0; i < 36; ++i) estimate.covariance[i] = r.covariance(i / 6, i % 6);
  estimate.protection_level_position = r.integrity.levels.position_m;
  estimate.protection_level_attitude = r.integrity.levels.attitude_deg;
  estimate.alert_limit_position = r.integrity.limits.position_m;
  estimate.alert_limit_attitude = r.integrity.limits.attitude_deg;
  estimate.integrity_risk = r.integrity.risk;
  tf2::toMsg(r.velocity, estimate.velocity.linear);
  tf2::toMsg(r.angular_velocity, estimate.velocity.angular);
  estimate.converged = r.icp.converged;
  estimate.iterations = static_cast<uint32_t>(r.icp.iterations);
  estimate.rms = r.icp.rms;
  estimate.fitness = r.icp.fitness;
  estimate.sensed_points = static_cast<uint32_t>(r.sensed_points);
  estimate.reference_points = static_cast<uint32_t>(r.reference_points);
  estimate.registration_ms = r.registration_ms;
  return estimate;
}

}  // namespace aar_registration
