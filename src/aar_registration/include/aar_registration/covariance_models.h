#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "aar_registration/types.h"

namespace aar_registration {

// [m] Stereo's range noise of one point at depth z_m [m]: sigma_Z = Z^2 sigma_d / (f b), with
// disparity noise sigma_d [px], focal length fx [px] and baseline [m].
double StereoRangeSigma(double z_m, double disparity_sigma, double fx, double baseline_m);

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

// The measurement that a posterior was made of. `posterior` combines a prior at `prior` [m, left-
// multiplied rotation; tanker frame] with covariance P and data of covariance R (the data's
// information alone inverted): in the tangent space at the prior, posterior = (P^-1 + R^-1)^-1
// (P^-1 prior + R^-1 data), so data = prior + (P + R) P^-1 (posterior - prior). The data is what a
// filter whose prediction is that prior may fuse with covariance R without counting the prior
// twice (exact for linear models; an alignment stopped short of its optimum is taken as there).
Eigen::Isometry3d DataOnlyMeasurement(const Eigen::Isometry3d& posterior,
                                      const Eigen::Isometry3d& prior, const Matrix6d& P,
                                      const Matrix6d& R);

}  // namespace aar_registration
