#include "aar_registration/icp.h"

#include "icp_target.h"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace aar_registration {
namespace {

// [m] PCL's GICP takes a distance: this one admits every pair on any aircraft-sized scene.
constexpr double kNoGate = 1e6;

pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const std::vector<Eigen::Vector3d>& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(points.size());
  for (const auto& p : points) {
    if (p.allFinite())
      cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                     static_cast<float>(p.z())));
  }
  return cloud;
}

// Sensed points moved by the current pose, each with the index of its target point.
using Pairs = std::vector<std::pair<Eigen::Vector3d, size_t>>;

// Matching: each finite source point under result->T_target_source paired with its nearest
// target point within sqrt(max_d2); RMS, fitness and correspondences of `result` describe them.
void Match(const Icp::Target& target, const std::vector<Eigen::Vector3d>& source, double max_d2,
           RegistrationResult* result, Pairs* pairs) {
  pairs->clear();
  double sum_d2 = 0.0;
  for (const auto& s : source) {
    if (!s.allFinite()) continue;
    const Eigen::Vector3d p = result->T_target_source * s;
    size_t index = 0;
    double d2 = 0.0;
    nanoflann::KNNResultSet<double> nearest(1);
    nearest.init(&index, &d2);
    target.tree->findNeighbors(nearest, p.data(), nanoflann::SearchParams());
    if (d2 > max_d2) continue;
    pairs->emplace_back(p, index);
    sum_d2 += d2;
  }
  result->correspondences = static_cast<int>(pairs->size());
  result->fitness = source.empty() ? 0.0 : static_cast<double>(pairs->size()) / source.size();
  result->rms = pairs->empty() ? 0.0 : std::sqrt(sum_d2 / pairs->size());
}

// The covariance of the pose of `pairs` (see RegistrationResult::covariance).
void EstimateCovariance(const Icp::Target& target, const IcpOptions& options, const Pairs& pairs,
                        RegistrationResult* result) {
  result->covariance.setZero();
  result->degenerate = false;
  const auto& tp = target.set.pts;
  const bool planes = options.metric == IcpMetric::kPointToPlane;
  const int rows_per_pair = planes ? 1 : 3;
  const int dof = static_cast<int>(pairs.size()) * rows_per_pair - 6;
  if (pairs.size() < static_cast<size_t>(options.min_correspondences) || dof <= 0) return;
  Matrix6d H = Matrix6d::Zero();
  double sum_r2 = 0.0;
  for (const auto& [p, i] : pairs) {
    if (planes) {  // r = n . (p - q), dr/d(w, t) = [p x n, n]
      const Eigen::Vector3d& n = target.normals[i];
      Vector6d J;
      J << p.cross(n), n;
      H += J * J.transpose();
      const double r = n.dot(p - tp[i]);
      sum_r2 += r * r;
    } else {  // r = p - q, dr/d(w, t) = [-[p]x, I]
      Eigen::Matrix<double, 3, 6> J;
      J << 0.0, p.z(), -p.y(), 1.0, 0.0, 0.0,  //
          -p.z(), 0.0, p.x(), 0.0, 1.0, 0.0,   //
          p.y(), -p.x(), 0.0, 0.0, 0.0, 1.0;
      H += J.transpose() * J;
      sum_r2 += (p - tp[i]).squaredNorm();
    }
  }
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(H);
  result->degenerate = !WellConditioned(eigen.eigenvalues());
  if (result->degenerate) return;
  const double correlation =
      std::max(1.0, static_cast<double>(pairs.size()) / options.independent_correspondences);
  const double sigma2 =
      std::max(sum_r2 / dof, options.min_residual_sigma * options.min_residual_sigma);
  result->covariance =
      correlation * sigma2 * eigen.operatorInverseSqrt() * eigen.operatorInverseSqrt();
}

// Solving, point to point: the rigid motion (in the target frame) that best moves the pairs
// together, in closed form (SVD, no reflection).
Eigen::Isometry3d PointToPointStep(const Icp::Target& target, const Pairs& pairs) {
  const auto& tp = target.set.pts;
  Eigen::Vector3d cs = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (const auto& [p, i] : pairs) cs += p, ct += tp[i];
  cs /= pairs.size();
  ct /= pairs.size();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const auto& [p, i] : pairs) H += (p - cs) * (tp[i] - ct).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = svd.matrixV() * D * svd.matrixU().transpose();
  step.translation() = ct - step.linear() * cs;
  return step;
}

// Solving, point to plane, linearised: minimise sum (n . (p + w x p + t - q))^2 over (w, t).
// None when a plane or a line leaves motions unconstrained.
std::optional<Eigen::Isometry3d> PointToPlaneStep(const Icp::Target& target, const Pairs& pairs) {
  const auto& tp = target.set.pts;
  Matrix6d A = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  for (const auto& [p, i] : pairs) {
    const Eigen::Vector3d& n = target.normals[i];
    Vector6d J;
    J << p.cross(n), n;
    A += J * J.transpose();
    b -= J * n.dot(p - tp[i]);
  }
  return SmallMotion(A, b);
}

// kGeneralizedPcl: PCL's GICP from the guess; RMS, fitness and covariance by this file's
// definitions, as for the other metrics.
RegistrationResult AlignGeneralized(const Icp::Target& target, const IcpOptions& options,
                                    const std::vector<Eigen::Vector3d>& source,
                                    const Eigen::Isometry3d& guess, double max_d2) {
  RegistrationResult result;
  result.T_target_source = guess;
  Gicp& gicp = *target.gicp;
  const auto cloud = ToPcl(source);
  if (cloud->size() < static_cast<size_t>(options.min_correspondences)) return result;
  gicp.setInputSource(cloud);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  gicp.align(aligned, guess.matrix().cast<float>());
  const Eigen::Matrix4d M = gicp.getFinalTransformation().cast<double>();
  result.T_target_source.linear() =  // float: re-orthonormalised
      Eigen::Quaterniond(Eigen::Matrix3d(M.topLeftCorner<3, 3>())).normalized().toRotationMatrix();
  result.T_target_source.translation() = M.topRightCorner<3, 1>();
  result.iterations = gicp.iterations();
  Pairs pairs;
  Match(target, source, max_d2, &result, &pairs);
  EstimateCovariance(target, options, pairs, &result);
  result.converged = gicp.hasConverged() && result.iterations < options.max_iterations &&
                     result.correspondences >= options.min_correspondences;
  return result;
}

// An iteration's pose with its pairs and statistics: a rise in RMS returns to the one before
// without matching again.
struct Iterate {
  Eigen::Isometry3d pose;
  Pairs pairs;
  double rms = std::numeric_limits<double>::infinity();
  int correspondences = 0;
  double fitness = 0.0;
};

}  // namespace

Icp::Icp(const IcpOptions& options) : options_(options) {
  if (options.max_iterations < 1) throw std::invalid_argument("max_iterations must be at least 1");
  if (!(options.max_correspondence_distance >= 0.0)) {
    throw std::invalid_argument("max_correspondence_distance must be >= 0 (0: no gate)");
  }
  if (!(options.min_rms_improvement >= 0.0))
    throw std::invalid_argument("min_rms_improvement must be >= 0");
  if (options.min_correspondences < 3)
    throw std::invalid_argument("min_correspondences must be at least 3");
  if (options.independent_correspondences < 1)
    throw std::invalid_argument("independent_correspondences must be at least 1");
  if (!(options.min_residual_sigma >= 0.0))
    throw std::invalid_argument("min_residual_sigma must be >= 0");
  const StereoNoise& n = options.stereo;
  if (!(n.ray_sigma_coefficient >= 0.0))
    throw std::invalid_argument("stereo ray_sigma_coefficient must be >= 0");
  if (!(n.plane_sigma > 0.0)) throw std::invalid_argument("stereo plane_sigma must be > 0");
  if (!(n.ray_reach > 0.0)) throw std::invalid_argument("stereo ray_reach must be > 0");
}

Icp::~Icp() = default;
Icp::Icp(Icp&&) noexcept = default;
Icp& Icp::operator=(Icp&&) noexcept = default;

bool Icp::has_target() const { return target_ && target_->tree; }

void Icp::SetTarget(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals) {
  if (points.empty()) throw std::invalid_argument("ICP target is empty");
  for (const auto& p : points) {
    if (!p.allFinite()) throw std::invalid_argument("ICP target holds a non-finite point");
  }
  const bool planes =
      options_.metric == IcpMetric::kPointToPlane || options_.metric == IcpMetric::kStereoRays;
  if (planes && normals.size() != points.size()) {
    throw std::invalid_argument("point-to-plane and stereo-ray ICP need a normal per target point");
  }
  auto target = std::make_unique<Target>();
  target->set.pts = std::move(points);
  target->normals = std::move(normals);
  target->tree =
      std::make_unique<KdTree>(3, target->set, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  target->tree->buildIndex();
  if (options_.metric == IcpMetric::kGeneralizedPcl) {
    target->gicp = std::make_unique<Gicp>();
    target->gicp->setInputTarget(ToPcl(target->set.pts));
    target->gicp->setMaximumIterations(options_.max_iterations);
    target->gicp->setMaxCorrespondenceDistance(options_.max_correspondence_distance > 0.0
                                                   ? options_.max_correspondence_distance
                                                   : kNoGate);
    target->gicp->setTransformationEpsilon(1e-10);
    target->gicp->setEuclideanFitnessEpsilon(options_.min_rms_improvement *
                                             options_.min_rms_improvement);
  }
  target_ = std::move(target);
}

RegistrationResult Icp::Align(const std::vector<Eigen::Vector3d>& source,
                              const Eigen::Isometry3d& guess,
                              const Eigen::Vector3d* source_eye) const {
  if (!has_target()) throw std::invalid_argument("ICP has no target");
  if (options_.metric == IcpMetric::kStereoRays) {
    if (source_eye == nullptr || !source_eye->allFinite())
      throw std::invalid_argument("stereo-ray ICP needs the camera's position (source_eye)");
    return AlignAlongRays(*target_, options_, source, guess, *source_eye);
  }
  const double max_d2 =
      options_.max_correspondence_distance > 0.0
          ? options_.max_correspondence_distance * options_.max_correspondence_distance
          : std::numeric_limits<double>::infinity();
  if (options_.metric == IcpMetric::kGeneralizedPcl)
    return AlignGeneralized(*target_, options_, source, guess, max_d2);

  RegistrationResult result;
  result.T_target_source = guess;
  Pairs pairs;
  pairs.reserve(source.size());
  Iterate previous{guess, {}};
  previous.pairs.reserve(source.size());
  for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
    result.iterations = iteration;
    Match(*target_, source, max_d2, &result, &pairs);
    if (result.correspondences < options_.min_correspondences) {
      result.converged = false;
      return result;
    }
    // Convergence: once the RMS stops falling (section 3.6). With stop_on_rms_rise a rise stops
    // too, at the pose before it; without, it iterates on.
    const double improvement = previous.rms - result.rms;
    const bool rose = improvement < 0.0 && options_.stop_on_rms_rise;
    if (rose) {
      result.T_target_source = previous.pose;
      pairs.swap(previous.pairs);
      result.correspondences = previous.correspondences;
      result.fitness = previous.fitness;
      result.rms = previous.rms;
    }
    if (rose || result.rms < options_.rms_epsilon ||
        (improvement >= 0.0 && improvement <= options_.min_rms_improvement)) {
      result.converged = true;
      EstimateCovariance(*target_, options_, pairs, &result);
      return result;
    }
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    if (options_.metric == IcpMetric::kPointToPoint) {
      step = PointToPointStep(*target_, pairs);
    } else {
      const std::optional<Eigen::Isometry3d> motion = PointToPlaneStep(*target_, pairs);
      if (!motion) {
        result.converged = false;
        return result;
      }
      step = *motion;
    }
    previous.rms = result.rms;
    previous.pose = result.T_target_source;
    previous.pairs.swap(pairs);  // Match refills `pairs` next iteration
    previous.correspondences = result.correspondences;
    previous.fitness = result.fitness;
    result.T_target_source = step * result.T_target_source;
  }
  Match(*target_, source, max_d2, &result, &pairs);  // statistics of the transform returned
  EstimateCovariance(*target_, options_, pairs, &result);
  result.converged = false;  // out of iterations while still improving
  return result;
}

}  // namespace aar_registration
