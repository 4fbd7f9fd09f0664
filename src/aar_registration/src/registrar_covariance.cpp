// The registrar's covariance models: a start's prior, ICP's covariance with stereo's range noise,
// and the errors that persist across frames (docs/INTEGRITY.md).
#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <aar_geometry/pose.h>

#include "aar_registration/covariance_models.h"
#include "aar_registration/registrar.h"

namespace aar_registration {

Matrix6d Registrar::StartCovariance() const {
  Vector6d sigma;
  sigma << Eigen::Vector3d::Constant(options_.outline.start_sigma_position),
      Eigen::Vector3d::Constant(options_.outline.start_sigma_rotation);
  return sigma.cwiseAbs2().asDiagonal();
}

Matrix6d Registrar::IcpCovariance(const RegistrarResult& out, const OutlineFrame* frame) const {
  Matrix6d covariance = CovarianceInTanker(out.icp.covariance, out.T_tanker_receiver_registered);
  const double sigma_d = options_.outline.disparity_sigma;
  if (!frame || !(sigma_d > 0.0)) return covariance;
  // The first rig's (stereo's points are its): further rigs are a few metres from it.
  const aar_alignment::PinholeCamera& left = frame->left_camera;
  const double baseline = frame->baseline();
  const Eigen::Vector3d ray =
      out.T_tanker_receiver_registered.translation() - left.T_tanker_optical.translation();
  const double z = ray.norm();
  if (!(baseline > 0.0) || !(z > 0.0)) return covariance;
  const double sigma_z = StereoRangeSigma(z, sigma_d, left.fx, baseline);  // [m] of one point
  const double independent = std::max(
      1.0, std::min<double>(out.icp.correspondences, options_.icp.independent_correspondences));
  const Eigen::Vector3d u = ray / z;
  covariance.topLeftCorner<3, 3>() += u * u.transpose() * sigma_z * sigma_z / independent;
  if (options_.outline.disparity_rotation)
    covariance.bottomRightCorner<3, 3>() += RangeNoiseRotation(
        reference_points_, out.T_tanker_receiver_registered.linear(), u, sigma_z, independent);
  return covariance;
}

Eigen::Matrix3d RangeNoiseRotation(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Matrix3d& R, const Eigen::Vector3d& u,
                                   double sigma_z, double independent) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  if (points.size() < 3 || !(independent > 0.0)) return c;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    mean += p;
    scatter += p * p.transpose();
  }
  const double n = static_cast<double>(points.size());
  mean /= n;
  scatter = scatter / n - mean * mean.transpose();
  // The spread across the ray, in the tanker frame.
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - u * u.transpose();
  const Eigen::Matrix3d spread = across * R * scatter * R.transpose() * across;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
  for (int i = 0; i < 3; ++i) {
    const double l2 = eig.eigenvalues()(i);  // [m^2] mean squared lever arm along v
    const Eigen::Vector3d v = eig.eigenvectors().col(i);
    if (!(l2 > 1e-6) || std::abs(v.dot(u)) > 0.5) continue;  // u itself: no lever arm
    const Eigen::Vector3d axis = u.cross(v).normalized();    // turning about it moves v in range
    c += axis * axis.transpose() * sigma_z * sigma_z / (independent * l2);
  }
  return c;
}

double StereoRangeSigma(double z_m, double disparity_sigma, double fx, double baseline_m) {
  return z_m * z_m * disparity_sigma / (fx * baseline_m);
}

Matrix6d PersistentSizeCovariance(double range_m, const Eigen::Vector3d& u, double sigma_px,
                                  double fx, double size_m) {
  Matrix6d c = Matrix6d::Zero();
  if (!(range_m > 0.0) || !(sigma_px > 0.0) || !(fx > 0.0) || !(size_m > 0.0)) return c;
  const double turn = range_m * sigma_px / (fx * size_m);  // [rad]
  const double along = turn * range_m;                     // [m]
  c.topLeftCorner<3, 3>() = along * along * u * u.transpose();
  c.bottomRightCorner<3, 3>().diagonal().setConstant(turn * turn);
  return c;
}

Matrix6d Registrar::PersistentCovariance(const Eigen::Isometry3d& T,
                                         const OutlineFrame* frame) const {
  if (!frame) return Matrix6d::Zero();
  // From the first rig's left camera: further rigs are a few metres from it, the range far more.
  const Eigen::Vector3d ray = T.translation() - frame->left_camera.T_tanker_optical.translation();
  const double z = ray.norm();
  if (!(z > 0.0)) return Matrix6d::Zero();
  return PersistentSizeCovariance(z, ray / z, options_.persistent_error.pixel_sigma,
                                  frame->left_camera.fx, receiver_size_m_);
}

Eigen::Isometry3d DataOnlyMeasurement(const Eigen::Isometry3d& posterior,
                                      const Eigen::Isometry3d& prior, const Matrix6d& P,
                                      const Matrix6d& R) {
  const Eigen::AngleAxisd turn(posterior.linear() * prior.linear().transpose());
  Vector6d delta;
  delta << posterior.translation() - prior.translation(), turn.angle() * turn.axis();
  const Eigen::LLT<Matrix6d> P_llt(P);  // fails unless P is positive definite
  if (P_llt.info() != Eigen::Success) return posterior;
  const Vector6d data = (P + R) * P_llt.solve(delta);
  if (!data.allFinite()) return posterior;
  Eigen::Isometry3d out = prior;
  out.translation() += data.head<3>();
  out.linear() = aar_geometry::RotationExp(data.tail<3>()) * prior.linear();
  return out;
}

}  // namespace aar_registration
