#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "aar_registration/covariance_models.h"

namespace aar_registration {
namespace {

// A wing along y (16 points from -7.5 m to 7.5 m, mean squared lever arm 21.25 m^2) seen along
// x: range noise turns it about z only, by sigma_z^2 / (N l^2); nothing about x (the ray) or y
// (the wing has no lever arm along z).
TEST(CovarianceModels, RangeNoiseTurnsAWingAboutTheAxisAcrossBoth) {
  std::vector<Eigen::Vector3d> wing;
  for (int i = 0; i < 16; ++i) wing.emplace_back(0.0, -7.5 + i, 0.0);
  const Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  const Eigen::Matrix3d c = RangeNoiseRotation(wing, Eigen::Matrix3d::Identity(), u, 2.2, 20.0);
  const double l2 = 21.25;
  EXPECT_NEAR(c(2, 2), 2.2 * 2.2 / (20.0 * l2), 1e-12);  // 0.0114 rad^2: 6.1 deg
  EXPECT_NEAR(c(0, 0), 0.0, 1e-12);
  EXPECT_NEAR(c(1, 1), 0.0, 1e-12);
  // The same wing rolled 90 deg into z: now it turns about y.
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).matrix();
  const Eigen::Matrix3d rolled = RangeNoiseRotation(wing, roll, u, 2.2, 20.0);
  EXPECT_NEAR(rolled(1, 1), c(2, 2), 1e-12);
  EXPECT_NEAR(rolled(2, 2), 0.0, 1e-12);
  EXPECT_TRUE(RangeNoiseRotation({}, Eigen::Matrix3d::Identity(), u, 2.2, 20.0).isZero());
}

// A 21.8 m receiver at 35 m whose apparent size is 0.2 px off in a 1108 px camera: 1.0 cm in
// range along the ray, 0.017 deg of turn.
TEST(CovarianceModels, APersistentSizeErrorMovesTheRangeAndTurns) {
  const Eigen::Vector3d u = Eigen::Vector3d(-1.0, 0.0, -0.3).normalized();
  const Matrix6d c = PersistentSizeCovariance(35.0, u, 0.2, 1108.0, 21.8);
  const double turn = 35.0 * 0.2 / (1108.0 * 21.8);
  EXPECT_NEAR(std::sqrt(u.dot(c.topLeftCorner<3, 3>() * u)), 35.0 * turn, 1e-12);
  EXPECT_NEAR(35.0 * turn, 0.0101, 1e-4);
  const Eigen::Vector3d across = u.cross(Eigen::Vector3d::UnitY()).normalized();
  EXPECT_NEAR(across.dot(c.topLeftCorner<3, 3>() * across), 0.0, 1e-15);
  EXPECT_NEAR(c(3, 3), turn * turn, 1e-15);
  EXPECT_TRUE(PersistentSizeCovariance(35.0, u, 0.0, 1108.0, 21.8).isZero());
}

}  // namespace
}  // namespace aar_registration
