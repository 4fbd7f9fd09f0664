#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace aar_geometry {

constexpr double DegToRad(double deg) { return deg * M_PI / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / M_PI; }

// Aircraft attitude angles [rad], intrinsic z-y'-x'' (yaw about z, then pitch about the new y,
// then roll about the newest x): R = Rz(yaw) * Ry(pitch) * Rx(roll), as in REP-103 and tf.
struct RollPitchYaw {
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;
};

Eigen::Matrix3d RotationFromRollPitchYaw(const RollPitchYaw& rpy);

// Inverse of RotationFromRollPitchYaw with pitch in [-pi/2, pi/2] and roll, yaw in (-pi, pi].
// At pitch = +/-90 deg only roll -/+ yaw is defined: roll is then reported as 0. Note the order:
// Eigen's eulerAngles(2, 1, 0) gives (yaw, pitch, roll). Throws std::invalid_argument for a
// matrix that is not a rotation (determinant off 1 by more than 1e-3, or not finite).
RollPitchYaw RollPitchYawFromRotation(const Eigen::Matrix3d& R);

// Pose from a position [m] and attitude [rad], e.g. one flight-path row.
Eigen::Isometry3d MakeTransform(const Eigen::Vector3d& translation, const RollPitchYaw& rpy);

// REP-103: a body frame is x forward, y left, z up; the optical frame of a camera on it is
// z forward, x right, y down. R_body_optical maps optical coordinates into the body frame.
Eigen::Matrix3d R_body_optical();
Eigen::Isometry3d T_body_optical();

// The rotation of rotation vector `w`: |w| [rad] about w / |w| (SO(3)'s exponential map); the
// identity below 1e-12 rad.
Eigen::Matrix3d RotationExp(const Eigen::Vector3d& w);

// T_parent_body moved on by `dt` [s] at constant velocity: translation + velocity * dt and the
// rotation turned by angular_velocity * dt about the parent's axes (velocity [m/s] and
// angular_velocity [rad/s] both in the parent frame, as the tracking filter and
// aar_msgs/PoseEstimate.velocity give them). dt may be negative.
Eigen::Isometry3d ExtrapolatePose(const Eigen::Isometry3d& T_parent_body,
                                  const Eigen::Vector3d& velocity,
                                  const Eigen::Vector3d& angular_velocity, double dt);

}  // namespace aar_geometry
