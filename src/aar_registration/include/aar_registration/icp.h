#pragma once

#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "aar_registration/types.h"

namespace aar_registration {

// Point-to-point (thesis) and point-to-plane are implemented here; generalized ICP is PCL's
// GeneralizedIterativeClosestPoint (plane-to-plane with covariances from 20 neighbours).
// kStereoRays (ours, issue 29; ray_icp.cpp): each sensed point pairs with the reference point
// nearest to its camera ray, not to the point, and the pair's point-to-plane residual is weighted
// by stereo's noise along that ray. Stereo scatters a point along its ray, so a nearest-point pair
// moves with the noise and, on a curved surface, is biased outward (by about sigma_Z^2 / 2R at
// grazing rays: centimetres near contact); a pair found along the ray does not move with it, and
// its plane residual is zero-mean. Needs the sensor's position (Align's `source_eye`).
enum class IcpMetric { kPointToPoint, kPointToPlane, kGeneralizedPcl, kStereoRays };

// Stereo's noise as kStereoRays weighs it: along the ray sigma_Z = ray_sigma_coefficient * Z^2
// (sigma_d / (f b): disparity noise over focal length times baseline, Z the point's range from
// the eye), and plane_sigma for everything else (lateral noise, the reference's sampling).
struct StereoNoise {
  double ray_sigma_coefficient = 0.00045;  // [1/m] 0.25 px on the shipped rig (f b = 554 px m)
  double plane_sigma = 0.02;               // [m]
  // [m] A reference point farther than this from a sensed point's ray is no pair for it (about
  // the reference's sample spacing, 9 cm, with room).
  double ray_reach = 0.15;
};

struct IcpOptions {
  IcpMetric metric = IcpMetric::kPointToPoint;  // thesis
  int max_iterations = 30;                      // thesis
  // [m] Pairs farther apart are dropped. 0 (thesis): every sensed point pairs with its nearest
  // reference point, so ICP gives a pose on every frame with points. Ours (tracking): 1 m.
  double max_correspondence_distance = 0.0;
  // [m] Stop once the RMS falls by no more than this. 0 (thesis section 3.6): when the RMS
  // stops falling.
  double min_rms_improvement = 0.0;
  // Thesis: a rise of the RMS also stops ICP, at the pose before the rise. Off, a rise iterates
  // on (point-to-plane steps can overshoot far from the solution; a gate lets pairs enter).
  bool stop_on_rms_rise = true;
  double rms_epsilon = 1e-4;     // [m] stop when RMS falls below
  int min_correspondences = 10;  // fewer: no pose
  // The measurement covariance treats the matched pairs as this many independent ones at most:
  // stereo errors of neighbouring points are strongly correlated (one disparity error smears a
  // patch), so thousands of pairs do not pin a pose down thousands of times better.
  int independent_correspondences = 20;
  // [m] The residual sigma in the covariance is at least this: noise-free clouds (synthetic ones)
  // would otherwise claim a perfect pose.
  double min_residual_sigma = 0.001;
  StereoNoise stereo;  // kStereoRays only
};

// T_target_source maps source points onto the target.
struct RegistrationResult {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  bool converged = false;  // stopped by the RMS criteria (not out of iterations), enough pairs
  int iterations = 0;
  double rms = 0.0;      // [m] over the correspondences of T_target_source
  double fitness = 0.0;  // share of source points with a correspondence
  int correspondences = 0;
  // Of the final pose, from the Gauss-Newton Hessian of the metric's residuals at the final
  // pairs: sigma^2 (H^T H)^-1, sigma^2 from the residuals, scaled up by correspondences /
  // independent_correspondences when larger. Order [rotation (rad), translation (m)] of a
  // left perturbation T_target_source' = Exp(xi) T_target_source, both in the target frame.
  // Zero when there were too few pairs or the geometry leaves a motion unconstrained
  // (`degenerate`).
  Matrix6d covariance = Matrix6d::Zero();
  bool degenerate = false;  // the pairs leave a rigid motion (nearly) unconstrained
};

// Iterative closest point against a fixed target whose KD-tree is built once by SetTarget and
// reused for every Align until the target changes.
class Icp {
 public:
  explicit Icp(const IcpOptions& options);  // throws std::invalid_argument for nonsense options
  ~Icp();
  Icp(Icp&&) noexcept;
  Icp& operator=(Icp&&) noexcept;

  // Point-to-plane needs one unit normal per target point. Throws std::invalid_argument for an
  // empty target, non-finite points or missing normals.
  void SetTarget(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals = {});
  bool has_target() const;

  // Throws std::invalid_argument without a target; an empty source gives converged = false.
  // Not to be called concurrently on one object (the generalized metric keeps PCL state).
  // `source_eye`: the camera the source points were measured from, in the source frame
  // (kStereoRays needs it: std::invalid_argument without; the other metrics ignore it).
  RegistrationResult Align(const std::vector<Eigen::Vector3d>& source,
                           const Eigen::Isometry3d& T_target_source_guess,
                           const Eigen::Vector3d* source_eye = nullptr) const;

  const IcpOptions& options() const { return options_; }

  struct Target;  // defined in src/icp_target.h

 private:
  IcpOptions options_;
  std::unique_ptr<Target> target_;
};

}  // namespace aar_registration
