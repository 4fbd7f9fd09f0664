// IcpMetric::kStereoRays: pairs found along each sensed point's camera ray, point-to-plane
// residuals weighted by stereo's noise along that ray (icp.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Eigenvalues>

#include "icp_target.h"

namespace aar_registration {
namespace {

// The target's points binned by their direction from an eye, on a grid of angles fine enough
// that every point within `reach` of a ray lies in the 3 x 3 cells around the ray's own.
class RayIndex {
 public:
  RayIndex(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& eye, double reach)
      : points_(points), eye_(eye) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto& p : points) centroid += p;
    const Eigen::Vector3d z = (centroid / points.size() - eye).normalized();
    const Eigen::Vector3d x = z.unitOrthogonal();
    basis_.row(0) = x.transpose();
    basis_.row(1) = z.cross(x).transpose();
    basis_.row(2) = z.transpose();
    double nearest = std::numeric_limits<double>::infinity();  // [m] depth of the nearest point
    for (const auto& p : points) {
      const double depth = z.dot(p - eye);
      if (depth > 0.0) nearest = std::min(nearest, depth);
    }
    // A point `reach` off a ray at depth d is reach / d off it in angle: the nearest depth bounds
    // that for all (and at least 1 m keeps the grid finite).
    cell_ = reach / std::max(1.0, nearest);
    cells_.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      int64_t key = 0;
      if (Key(points[i], 0, 0, &key)) cells_.emplace_back(key, static_cast<int>(i));
    }
    std::sort(cells_.begin(), cells_.end());
  }

  // The target point nearest to the ray from `eye` through `p` (target frame) and its distance
  // from the ray; -1 when none lies within the 3 x 3 cells.
  int Nearest(const Eigen::Vector3d& eye, const Eigen::Vector3d& p, double* distance) const {
    const Eigen::Vector3d u = (p - eye).normalized();
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int di = -1; di <= 1; ++di) {
      for (int dj = -1; dj <= 1; ++dj) {
        int64_t key = 0;
        if (!Key(p, di, dj, &key)) return -1;
        const auto first = std::lower_bound(cells_.begin(), cells_.end(),
                                            std::make_pair(key, std::numeric_limits<int>::min()));
        for (auto it = first; it != cells_.end() && it->first == key; ++it) {
          const double d2 = (points_[it->second] - eye).cross(u).squaredNorm();
          if (d2 < best_d2) best_d2 = d2, best = it->second;
        }
      }
    }
    *distance = std::sqrt(best_d2);
    return best;
  }

 private:
  // The cell of q's direction from the index's eye, moved by (di, dj) cells.
  bool Key(const Eigen::Vector3d& q, int di, int dj, int64_t* key) const {
    const Eigen::Vector3d v = basis_ * (q - eye_);
    if (!(v.z() > 0.0)) return false;  // behind the eye
    const double a = v.x() / v.z() / cell_, b = v.y() / v.z() / cell_;
    constexpr double kHalf = 1 << 30;
    if (!(std::abs(a) < kHalf - 2 && std::abs(b) < kHalf - 2)) return false;
    const int64_t i = static_cast<int64_t>(std::floor(a)) + di + (1 << 30);
    const int64_t j = static_cast<int64_t>(std::floor(b)) + dj + (1 << 30);
    *key = (i << 31) | j;
    return true;
  }

  const std::vector<Eigen::Vector3d>& points_;
  Eigen::Vector3d eye_;
  Eigen::Matrix3d basis_;
  double cell_ = 1.0;                           // [rad]
  std::vector<std::pair<int64_t, int>> cells_;  // (cell, point), sorted
};

struct RayPair {
  Eigen::Vector3d p;  // the transformed source point
  size_t target = 0;
  double residual = 0.0;  // [m] n . (p - q)
  double weight = 0.0;    // [1/m^2] the residual's inverse variance
};

// One Align: the pairs of the current transform and the weighted Gauss-Newton steps.
class RayAlignment {
 public:
  RayAlignment(const Icp::Target& target, const IcpOptions& options,
               const std::vector<Eigen::Vector3d>& source, const Eigen::Isometry3d& guess,
               const Eigen::Vector3d& eye)
      : target_(target),
        options_(options),
        source_(source),
        eye_(eye),
        index_(target.set.pts, guess * eye, options.stereo.ray_reach) {
    result_.T_target_source = guess;
    pairs_.reserve(source.size());
  }

  RegistrationResult Run();

 private:
  void Match();
  // The weighted normal equations of the linearised residuals r + J . (w, t), J = [p x n, n].
  void NormalEquations(Matrix6d* A, Vector6d* b, double* chi2) const;
  void EstimateCovariance(const Matrix6d& A, double chi2);

  const Icp::Target& target_;
  const IcpOptions& options_;
  const std::vector<Eigen::Vector3d>& source_;
  const Eigen::Vector3d eye_;  // source frame
  const RayIndex index_;
  std::vector<RayPair> pairs_;
  RegistrationResult result_;
};

// Pairs of the current transform; the result's RMS (of the plane residuals) and fitness.
void RayAlignment::Match() {
  const auto& tp = target_.set.pts;
  const StereoNoise& noise = options_.stereo;
  const double plane2 = noise.plane_sigma * noise.plane_sigma;
  const double gate = options_.max_correspondence_distance;
  const Eigen::Vector3d e = result_.T_target_source * eye_;
  pairs_.clear();
  double sum_r2 = 0.0;
  for (const Eigen::Vector3d& s : source_) {
    if (!s.allFinite()) continue;
    RayPair pair;
    pair.p = result_.T_target_source * s;
    double off_ray = 0.0;
    const int i = index_.Nearest(e, pair.p, &off_ray);
    if (i < 0 || off_ray > noise.ray_reach) continue;
    const Eigen::Vector3d& n = target_.normals[i];
    const Eigen::Vector3d ray = tp[i] - e;
    const double cos_incidence = n.dot(ray.normalized());
    // The range noise at the reference point's range, not the sensed point's: the latter moves
    // with the noise, and weights that grow as points come nearer would pull the estimate toward
    // the camera.
    const double sigma_z = noise.ray_sigma_coefficient * ray.squaredNorm();
    pair.target = static_cast<size_t>(i);
    pair.residual = n.dot(pair.p - tp[i]);
    pair.weight = 1.0 / (sigma_z * sigma_z * cos_incidence * cos_incidence + plane2);
    // The gate, or three sigmas of this pair's noise when that is wider (far out, stereo's range
    // noise is metres).
    if (gate > 0.0 && std::abs(pair.residual) > std::max(gate, 3.0 / std::sqrt(pair.weight)))
      continue;
    sum_r2 += pair.residual * pair.residual;
    pairs_.push_back(pair);
  }
  result_.correspondences = static_cast<int>(pairs_.size());
  result_.fitness = source_.empty() ? 0.0 : static_cast<double>(pairs_.size()) / source_.size();
  result_.rms = pairs_.empty() ? 0.0 : std::sqrt(sum_r2 / pairs_.size());
}

void RayAlignment::NormalEquations(Matrix6d* A, Vector6d* b, double* chi2) const {
  A->setZero(), b->setZero(), *chi2 = 0.0;
  for (const RayPair& pair : pairs_) {
    const Eigen::Vector3d& n = target_.normals[pair.target];
    Vector6d J;
    J << pair.p.cross(n), n;
    *A += pair.weight * J * J.transpose();
    *b -= pair.weight * pair.residual * J;
    *chi2 += pair.weight * pair.residual * pair.residual;
  }
}

// The covariance of the current pairs' pose: the inverse weighted Hessian, scaled by the
// residuals when they exceed the noise model and by the correlation of neighbouring points.
void RayAlignment::EstimateCovariance(const Matrix6d& A, double chi2) {
  result_.covariance.setZero();
  const int dof = static_cast<int>(pairs_.size()) - 6;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(A);
  result_.degenerate = !WellConditioned(eigen.eigenvalues());
  if (result_.degenerate || dof <= 0) return;
  const double correlation =
      std::max(1.0, static_cast<double>(pairs_.size()) / options_.independent_correspondences);
  const double variance_factor = std::max(1.0, chi2 / dof);
  result_.covariance =
      correlation * variance_factor * eigen.operatorInverseSqrt() * eigen.operatorInverseSqrt();
}

// Converged once the RMS stops falling (or, with stop_on_rms_rise, at the pose before a rise),
// as the other metrics.
RegistrationResult RayAlignment::Run() {
  double previous_rms = std::numeric_limits<double>::infinity();
  Eigen::Isometry3d previous_pose = result_.T_target_source;
  Matrix6d A;
  Vector6d b;
  double chi2 = 0.0;
  for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
    result_.iterations = iteration;
    Match();
    if (result_.correspondences < options_.min_correspondences) return result_;
    const double improvement = previous_rms - result_.rms;
    const bool rose = improvement < 0.0 && options_.stop_on_rms_rise;
    if (rose) {
      result_.T_target_source = previous_pose;
      Match();
    }
    NormalEquations(&A, &b, &chi2);
    if (rose || result_.rms < options_.rms_epsilon ||
        (improvement >= 0.0 && improvement <= options_.min_rms_improvement)) {
      EstimateCovariance(A, chi2);
      result_.converged = true;
      return result_;
    }
    const std::optional<Eigen::Isometry3d> step = SmallMotion(A, b);
    if (!step) return result_;  // a motion left unconstrained
    previous_rms = result_.rms;
    previous_pose = result_.T_target_source;
    result_.T_target_source = *step * result_.T_target_source;
  }
  Match();  // statistics of the transform returned
  NormalEquations(&A, &b, &chi2);
  if (result_.correspondences >= options_.min_correspondences) EstimateCovariance(A, chi2);
  return result_;  // out of iterations while still improving: not converged
}

}  // namespace

RegistrationResult AlignAlongRays(const Icp::Target& target, const IcpOptions& options,
                                  const std::vector<Eigen::Vector3d>& source,
                                  const Eigen::Isometry3d& guess, const Eigen::Vector3d& eye) {
  return RayAlignment(target, options, source, guess, eye).Run();
}

}  // namespace aar_registration
