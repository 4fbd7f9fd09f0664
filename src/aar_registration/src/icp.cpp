#include "aar_registration/icp.h"

#include "icp_target.h"

#include <cmath>
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
  RegistrationResult result;
  result.T_target_source = guess;
  const double max_d2 =
      options_.max_correspondence_distance > 0.0
          ? options_.max_correspondence_distance * options_.max_correspondence_distance
          : std::numeric_limits<double>::infinity();
  std::vector<std::pair<Eigen::Vector3d, size_t>> pairs;  // transformed source point, target index
  pairs.reserve(source.size());
  // The iteration before: a rise in RMS returns to it without matching again.
  double previous_rms = std::numeric_limits<double>::infinity();
  Eigen::Isometry3d previous_pose = guess;
  std::vector<std::pair<Eigen::Vector3d, size_t>> previous_pairs;
  previous_pairs.reserve(source.size());
  int previous_correspondences = 0;
  double previous_fitness = 0.0;

  // Correspondences of the current transform; RMS and fitness of `result` describe it.
  auto match = [&]() {
    pairs.clear();
    double sum_d2 = 0.0;
    for (const auto& s : source) {
      if (!s.allFinite()) continue;
      const Eigen::Vector3d p = result.T_target_source * s;
      size_t index = 0;
      double d2 = 0.0;
      nanoflann::KNNResultSet<double> nearest(1);
      nearest.init(&index, &d2);
      target_->tree->findNeighbors(nearest, p.data(), nanoflann::SearchParams());
      if (d2 > max_d2) continue;
      pairs.emplace_back(p, index);
      sum_d2 += d2;
    }
    result.correspondences = static_cast<int>(pairs.size());
    result.fitness = source.empty() ? 0.0 : static_cast<double>(pairs.size()) / source.size();
    result.rms = pairs.empty() ? 0.0 : std::sqrt(sum_d2 / pairs.size());
  };

  // The covariance of the pose of the current pairs (see RegistrationResult::covariance).
  auto estimate_covariance = [&]() {
    result.covariance.setZero();
    result.degenerate = false;
    const auto& tp = target_->set.pts;
    const bool planes = options_.metric == IcpMetric::kPointToPlane;
    const int rows_per_pair = planes ? 1 : 3;
    const int dof = static_cast<int>(pairs.size()) * rows_per_pair - 6;
    if (pairs.size() < static_cast<size_t>(options_.min_correspondences) || dof <= 0) return;
    Matrix6d H = Matrix6d::Zero();
    double sum_r2 = 0.0;
    for (const auto& [p, i] : pairs) {
      if (planes) {  // r = n . (p - q), dr/d(w, t) = [p x n, n]
        const Eigen::Vector3d& n = target_->normals[i];
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
    result.degenerate = !WellConditioned(eigen.eigenvalues());
    if (result.degenerate) return;
    const double correlation =
        std::max(1.0, static_cast<double>(pairs.size()) / options_.independent_correspondences);
    const double sigma2 =
        std::max(sum_r2 / dof, options_.min_residual_sigma * options_.min_residual_sigma);
    result.covariance =
        correlation * sigma2 * eigen.operatorInverseSqrt() * eigen.operatorInverseSqrt();
  };

  if (options_.metric == IcpMetric::kGeneralizedPcl) {
    Gicp& gicp = *target_->gicp;
    const auto cloud = ToPcl(source);
    if (cloud->size() < static_cast<size_t>(options_.min_correspondences)) return result;
    gicp.setInputSource(cloud);
    pcl::PointCloud<pcl::PointXYZ> aligned;
    gicp.align(aligned, guess.matrix().cast<float>());
    const Eigen::Matrix4d M = gicp.getFinalTransformation().cast<double>();
    result.T_target_source.linear() =  // float: re-orthonormalised
        Eigen::Quaterniond(Eigen::Matrix3d(M.topLeftCorner<3, 3>()))
            .normalized()
            .toRotationMatrix();
    result.T_target_source.translation() = M.topRightCorner<3, 1>();
    result.iterations = gicp.iterations();
    match();  // RMS and fitness by the same definition as the other metrics
    estimate_covariance();
    result.converged = gicp.hasConverged() && result.iterations < options_.max_iterations &&
                       result.correspondences >= options_.min_correspondences;
    return result;
  }

  for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
    result.iterations = iteration;
    match();
    if (result.correspondences < options_.min_correspondences) {
      result.converged = false;
      return result;
    }
    // Converged once the RMS stops falling (section 3.6). With stop_on_rms_rise a rise stops
    // too, at the pose before it; without, it iterates on.
    const double improvement = previous_rms - result.rms;
    if (improvement < 0.0 && options_.stop_on_rms_rise) {
      result.T_target_source = previous_pose;
      pairs.swap(previous_pairs);
      result.correspondences = previous_correspondences;
      result.fitness = previous_fitness;
      result.rms = previous_rms;
      result.converged = true;
      estimate_covariance();
      return result;
    }
    if (result.rms < options_.rms_epsilon ||
        (improvement >= 0.0 && improvement <= options_.min_rms_improvement)) {
      result.converged = true;
      estimate_covariance();
      return result;
    }

    // One step: the rigid motion (in the target frame) that best moves the pairs together.
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    const auto& tp = target_->set.pts;
    if (options_.metric == IcpMetric::kPointToPoint) {
      Eigen::Vector3d cs = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
      for (const auto& [p, i] : pairs) cs += p, ct += tp[i];
      cs /= pairs.size();
      ct /= pairs.size();
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      for (const auto& [p, i] : pairs) H += (p - cs) * (tp[i] - ct).transpose();
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
      D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0
                    ? -1.0
                    : 1.0;  // no reflection
      step.linear() = svd.matrixV() * D * svd.matrixU().transpose();
      step.translation() = ct - step.linear() * cs;
    } else {
      // Linearised point-to-plane: minimise sum (n . (p + w x p + t - q))^2 over (w, t).
      Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      for (const auto& [p, i] : pairs) {
        const Eigen::Vector3d& n = target_->normals[i];
        Eigen::Matrix<double, 6, 1> J;
        J << p.cross(n), n;
        A += J * J.transpose();
        b -= J * n.dot(p - tp[i]);
      }
      // A plane or a line leaves motions unconstrained: refuse.
      const std::optional<Eigen::Isometry3d> motion = SmallMotion(A, b);
      if (!motion) {
        result.converged = false;
        return result;
      }
      step = *motion;
    }
    previous_rms = result.rms;
    previous_pose = result.T_target_source;
    previous_pairs.swap(pairs);  // match() refills `pairs` next iteration
    previous_correspondences = result.correspondences;
    previous_fitness = result.fitness;
    result.T_target_source = step * result.T_target_source;
  }
  match();  // statistics of the transform returned
  estimate_covariance();
  result.converged = false;  // out of iterations while still improving
  return result;
}

}  // namespace aar_registration
