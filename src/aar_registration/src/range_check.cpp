#include "aar_registration/range_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "aar_registration/covariance_models.h"

namespace aar_registration {

std::string RangeCheck::ToString() const {
  std::ostringstream s;
  s.precision(3);
  s << "stereo's " << points << " points on the receiver's image";
  if (!enough) return s.str() + ", too few to check its range";
  s << " at a median " << median_depth << " m against the receiver's " << near << " to " << far
    << " m (tolerance " << tolerance << " m)";
  return s.str();
}

namespace {

constexpr int kMaskSize = 320;  // [px] across the receiver: which points fall on it, no more

// The farthest depth of the boom's vertices in the optical frame (0 without a boom).
double BoomFarDepth(const std::vector<std::vector<Eigen::Vector3d>>& parts,
                    const Eigen::Isometry3d& T_optical_tanker) {
  double far = 0.0;
  for (const auto& part : parts)
    for (const Eigen::Vector3d& v : part) far = std::max(far, (T_optical_tanker * v).z());
  return far;
}

}  // namespace

RangeCheck CheckRange(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                      const aar_alignment::OutlineModel& model,
                      const aar_alignment::PinholeCamera& left, double baseline_m,
                      const std::vector<std::vector<Eigen::Vector3d>>& boom_parts_in_tanker,
                      const Eigen::Isometry3d& T_tanker_receiver,
                      const RangeCheckOptions& options) {
  RangeCheck check;
  const Eigen::Isometry3d T_optical_tanker = left.T_tanker_optical.inverse();
  const Eigen::Isometry3d T_optical_receiver = T_optical_tanker * T_tanker_receiver;
  check.near = std::numeric_limits<double>::infinity();
  check.far = -check.near;
  for (const Eigen::Vector3d& v : model.mesh().vertices) {
    const double z = (T_optical_receiver * v).z();
    check.near = std::min(check.near, z);
    check.far = std::max(check.far, z);
  }
  const aar_alignment::SilhouetteMask mask = model.Silhouette(left, T_tanker_receiver, kMaskSize);
  if (mask.image.empty()) return check;
  // The boom's leftover points lie in front of the receiver: set aside when the boom ends nearer.
  double beyond = BoomFarDepth(boom_parts_in_tanker, T_optical_tanker);
  if (!(beyond < check.near)) beyond = 0.0;
  std::vector<double> depths;
  for (const Eigen::Vector3d& p : sensed_in_tanker) {
    const Eigen::Vector3d q = T_optical_tanker * p;
    if (!(q.z() > beyond) || !mask.At(left.Project(q))) continue;
    depths.push_back(q.z());
  }
  check.points = static_cast<int>(depths.size());
  check.enough = check.points >= std::max(1, options.min_points);
  if (!check.enough) return check;
  auto middle = depths.begin() + depths.size() / 2;
  std::nth_element(depths.begin(), middle, depths.end());
  check.median_depth = *middle;
  const double z = check.median_depth;
  const int independent = std::max(1, std::min(check.points, options.independent_points));
  check.tolerance = options.sigmas *
                    StereoRangeSigma(z, options.disparity_sigma, left.fx, baseline_m) /
                    std::sqrt(static_cast<double>(independent));
  check.agrees = z >= check.near - check.tolerance && z <= check.far + check.tolerance;
  return check;
}

}  // namespace aar_registration
