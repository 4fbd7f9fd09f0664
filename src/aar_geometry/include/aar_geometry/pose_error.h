#pragma once

#include <string>

#include "aar_geometry/pose.h"

namespace aar_geometry {

// Regions of the approach by distance from the tanker origin to the receiver origin (thesis):
// A [70, 175] m, B [38, 70) m, C [32, 38) m; anything else is outside. Values match the
// REGION_* constants of aar_msgs/PoseError.
enum class Region { kOutside = 0, kA = 1, kB = 2, kC = 3 };

struct RegionBounds {
  double c_min = 32.0;   // [m]
  double b_min = 38.0;   // [m]
  double a_min = 70.0;   // [m]
  double a_max = 175.0;  // [m]
};

Region RegionOfRange(double range_m, const RegionBounds& bounds = {});
std::string RegionName(Region region);  // "A", "B", "C", "outside"

// Error of an estimated receiver pose against truth, both as T_tanker_receiver.
struct PoseError {
  double range_m = 0.0;  // [m] |t_truth|, the distance from the tanker origin
  Region region = Region::kOutside;
  // Estimate minus truth along the true receiver body axes: R_truth^T (t_est - t_truth) [m].
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  // Roll, pitch, yaw of R_truth^T * R_estimate [rad].
  RollPitchYaw orientation_rad;
};

PoseError ComputePoseError(const Eigen::Isometry3d& T_tanker_truth,
                           const Eigen::Isometry3d& T_tanker_estimate,
                           const RegionBounds& bounds = {});

}  // namespace aar_geometry
