#include "aar_geometry/pose.h"

#include <stdexcept>
#include <string>

namespace aar_geometry {

Eigen::Matrix3d RotationFromRollPitchYaw(const RollPitchYaw& rpy) {
  return (Eigen::AngleAxisd(rpy.yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

namespace {

// atan2 gives -pi for a -0.0 sine; the range promised is (-pi, pi].
double Wrap(double a) { return a <= -M_PI ? a + 2.0 * M_PI : a; }

}  // namespace

RollPitchYaw RollPitchYawFromRotation(const Eigen::Matrix3d& R) {
  // 1e-3: rotations that passed through float (PCL, messages) are off by ~1e-6; a reflection
  // is off by 2 and a scaled matrix by far more.
  if (!R.allFinite() || std::abs(R.determinant() - 1.0) > 1e-3) {
    throw std::invalid_argument("not a rotation matrix (determinant " +
                                std::to_string(R.determinant()) + ")");
  }
  RollPitchYaw rpy;
  // atan2 of both terms rather than asin(-R20): accurate near +/-90 deg, where asin is not.
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  rpy.pitch = std::atan2(-R(2, 0), cos_pitch);
  if (cos_pitch > 1e-9) {
    rpy.roll = Wrap(std::atan2(R(2, 1), R(2, 2)));
    rpy.yaw = Wrap(std::atan2(R(1, 0), R(0, 0)));
  } else {
    // Gimbal lock: R depends on yaw - roll (pitch +90) or yaw + roll (pitch -90) only.
    rpy.roll = 0.0;
    rpy.yaw = Wrap(std::atan2(-R(0, 1), R(1, 1)));
  }
  return rpy;
}

Eigen::Isometry3d MakeTransform(const Eigen::Vector3d& translation, const RollPitchYaw& rpy) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromRollPitchYaw(rpy);
  T.translation() = translation;
  return T;
}

Eigen::Matrix3d R_body_optical() {
  Eigen::Matrix3d R;
  // Columns: optical x (right) = -body y, optical y (down) = -body z, optical z (forward) = body x.
  R << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  return R;
}

Eigen::Isometry3d T_body_optical() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_body_optical();
  return T;
}

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Eigen::Isometry3d ExtrapolatePose(const Eigen::Isometry3d& T_parent_body,
                                  const Eigen::Vector3d& velocity,
                                  const Eigen::Vector3d& angular_velocity, double dt) {
  const Eigen::Vector3d phi = angular_velocity * dt;
  const double angle = phi.norm();
  Eigen::Isometry3d T = T_parent_body;
  T.translation() += velocity * dt;
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, phi / angle) * T_parent_body.linear();
  return T;
}

}  // namespace aar_geometry
