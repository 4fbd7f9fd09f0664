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

// A prior (the track's prediction) and the images' own data, combined as the alignment does; the
// measurement recovered from the combination is the data, in position and rotation, and an
// identity prior with no data spread gives the posterior back when R is zero.
TEST(CovarianceModels, TheDataIsRecoveredFromAPosteriorThatHoldsThePrior) {
  Eigen::Isometry3d prior = Eigen::Isometry3d::Identity();
  prior.translation() = Eigen::Vector3d(-130.0, 2.0, -25.0);
  prior.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1.0, 0.3).normalized()).matrix();
  Vector6d data;  // the data's offset from the prior: far in range, a little across, turned
  data << 3.0, 0.4, -0.2, 0.01, -0.02, 0.015;
  Matrix6d A = Matrix6d::Identity();
  A(0, 1) = 0.3;
  A(4, 3) = -0.2;
  const Matrix6d P = A * Vector6d(0.3, 0.05, 0.05, 1e-4, 2e-4, 1e-4).asDiagonal() * A.transpose();
  const Matrix6d R = Vector6d(4.0, 0.01, 0.02, 3e-4, 1e-4, 5e-4).asDiagonal();
  // The posterior's offset from the prior: (P^-1 + R^-1)^-1 R^-1 data.
  const Vector6d m = (P.inverse() + R.inverse()).ldlt().solve(R.inverse() * data);
  EXPECT_LT(m(0), 0.3 * data(0)) << "the posterior stays near the prior in range";
  Eigen::Isometry3d posterior = prior;
  posterior.translation() += m.head<3>();
  posterior.linear() =
      Eigen::AngleAxisd(m.tail<3>().norm(), m.tail<3>().normalized()).matrix() * prior.linear();
  const Eigen::Isometry3d got = DataOnlyMeasurement(posterior, prior, P, R);
  EXPECT_LT((got.translation() - prior.translation() - data.head<3>()).norm(), 1e-9);
  const Eigen::AngleAxisd turn(got.linear() * prior.linear().transpose());
  EXPECT_LT((turn.angle() * turn.axis() - data.tail<3>()).norm(), 1e-9);
  // No data information beyond the prior's means nothing to take out: R = 0 returns the posterior.
  EXPECT_TRUE(
      DataOnlyMeasurement(posterior, prior, P, Matrix6d::Zero()).isApprox(posterior, 1e-12));
  // A prior that is no covariance leaves the posterior as it is.
  EXPECT_TRUE(DataOnlyMeasurement(posterior, prior, Matrix6d::Zero(), R).isApprox(posterior));
}

}  // namespace
}  // namespace aar_registration
