#include "aar_geometry/pose_error.h"

namespace aar_geometry {

Region RegionOfRange(double range_m, const RegionBounds& bounds) {
  if (range_m >= bounds.a_min && range_m <= bounds.a_max) return Region::kA;
  if (range_m >= bounds.b_min && range_m < bounds.a_min) return Region::kB;
  if (range_m >= bounds.c_min && range_m < bounds.b_min) return Region::kC;
  return Region::kOutside;  // also NaN: every comparison above is false
}

std::string RegionName(Region region) {
  static const char* const kNames[] = {"outside", "A", "B", "C"};  // by the enum's values
  const int i = static_cast<int>(region);
  return i >= 1 && i <= 3 ? kNames[i] : kNames[0];
}

PoseError ComputePoseError(const Eigen::Isometry3d& T_tanker_truth,
                           const Eigen::Isometry3d& T_tanker_estimate, const RegionBounds& bounds) {
  PoseError error;
  error.range_m = T_tanker_truth.translation().norm();
  error.region = RegionOfRange(error.range_m, bounds);
  const Eigen::Matrix3d R_truth_tanker = T_tanker_truth.linear().transpose();
  error.position_m =
      R_truth_tanker * (T_tanker_estimate.translation() - T_tanker_truth.translation());
  error.orientation_rad = RollPitchYawFromRotation(R_truth_tanker * T_tanker_estimate.linear());
  return error;
}

}  // namespace aar_geometry
