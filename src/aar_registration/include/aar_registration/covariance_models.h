#pragma once

#include <vector>

#include <Eigen/Core>

#include "aar_registration/types.h"

namespace aar_registration {

// [rad^2, tanker frame] The rotation covariance that a range noise of sigma_z [m] along the unit
// ray `u` (tanker frame), on each of `independent` points, gives a body whose points (its frame)
// are turned by R into the tanker frame: a point at lever arm l across the ray moves l dtheta in
// range when the body turns about the axis across both, so about u x v the variance is
// sigma_z^2 / (independent l_v^2), l_v^2 the points' mean squared spread along v.
Eigen::Matrix3d RangeNoiseRotation(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Matrix3d& R, const Eigen::Vector3d& u,
                                   double sigma_z, double independent);

// [m^2, rad^2] The covariance of a receiver of size `size_m` [m] at `range_m` [m] along the unit
// ray `u` whose apparent size is off by sigma_px [px] in a camera of focal length fx [px]: range
// by Z^2 sigma_px / (fx W) along u, a turn of Z sigma_px / (fx W) about every axis.
Matrix6d PersistentSizeCovariance(double range_m, const Eigen::Vector3d& u, double sigma_px,
                                  double fx, double size_m);

}  // namespace aar_registration
