#pragma once

#include <string>
#include <vector>

#include <aar_alignment/outline.h>
#include <Eigen/Geometry>

namespace aar_registration {

// Whether stereo's points agree with a pose's range: a check that does not share the outline's
// errors. A start from a few lines of the receiver's outline can fit at the wrong range (the
// RQ-4's long, slender wings fit 35 m too far at 101 m) and its own outline keeps agreeing with
// it; stereo measures range directly, with sigma_Z = Z^2 sigma_d / (f b) per point.
struct RangeCheckOptions {
  // The median depth of stereo's points on the receiver's image must lie within this many
  // sigma_Z of the receiver's depth at the pose (between its nearest and farthest vertex).
  double sigmas = 3.0;
  double disparity_sigma = 0.25;  // [px] sigma_d
  int min_points = 10;            // fewer points on the receiver's image: no verdict
  // The median of N points with independent errors is sigma_Z / sqrt(N) sure, about; stereo's
  // errors are not independent (disparity biases shared by neighbours), so at most this many
  // count: the tolerance is sigmas * sigma_Z / sqrt(min(N, independent_points)). 1: one point's.
  int independent_points = 1;
};

struct RangeCheck {
  int points = 0;                // stereo's points on the receiver's image, beyond the boom
  bool enough = false;           // points >= min_points: the check has a verdict
  bool agrees = false;           // enough, and the median within the tolerance
  double median_depth = 0.0;     // [m] of those points, left optical frame
  double near = 0.0, far = 0.0;  // [m] the receiver's depth at the pose
  double tolerance = 0.0;        // [m] sigmas * sigma_Z at median_depth / sqrt(independent)

  std::string ToString() const;  // "stereo's N points at M m against the receiver's A to B m ..."
};

// Stereo's points (tanker frame) that fall on the receiver's silhouette at T_tanker_receiver in
// the left image and lie beyond the boom (farther than its farthest vertex, when that is nearer
// than the receiver), against the receiver's depth at T. `baseline_m` is the rig's.
RangeCheck CheckRange(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                      const aar_alignment::OutlineModel& model,
                      const aar_alignment::PinholeCamera& left, double baseline_m,
                      const std::vector<std::vector<Eigen::Vector3d>>& boom_parts_in_tanker,
                      const Eigen::Isometry3d& T_tanker_receiver, const RangeCheckOptions& options);

}  // namespace aar_registration
