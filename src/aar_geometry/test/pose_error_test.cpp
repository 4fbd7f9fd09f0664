#include "aar_geometry/pose_error.h"

#include <gtest/gtest.h>

#include <limits>

namespace aar_geometry {
namespace {

TEST(PoseError, PerfectEstimateHasNoError) {
  const Eigen::Isometry3d T = MakeTransform({-30.0, 4.0, -18.0}, {0.05, -0.02, 0.3});
  const PoseError e = ComputePoseError(T, T);
  EXPECT_NEAR(e.range_m, std::sqrt(30.0 * 30.0 + 16.0 + 18.0 * 18.0), 1e-12);
  EXPECT_EQ(e.region, Region::kC);
  EXPECT_NEAR(e.position_m.norm(), 0.0, 1e-12);
  EXPECT_NEAR(e.orientation_rad.roll, 0.0, 1e-12);
  EXPECT_NEAR(e.orientation_rad.pitch, 0.0, 1e-12);
  EXPECT_NEAR(e.orientation_rad.yaw, 0.0, 1e-12);
}

TEST(PoseError, PositionErrorIsInTheTrueBodyFrame) {
  // Truth yawed 90 deg left: its body x is tanker +y and its body y is tanker -x.
  const Eigen::Isometry3d truth = MakeTransform({-50.0, 0.0, -10.0}, {0.0, 0.0, DegToRad(90.0)});
  Eigen::Isometry3d estimate = truth;
  estimate.translation() += Eigen::Vector3d(1.0, 0.0, 0.0);  // 1 m along tanker x
  PoseError e = ComputePoseError(truth, estimate);
  EXPECT_TRUE(e.position_m.isApprox(Eigen::Vector3d(0.0, -1.0, 0.0), 1e-12))
      << e.position_m.transpose();

  // Truth pitched 90 deg nose down: body x is tanker -z; an estimate 0.5 m low is +0.5 m in x.
  const Eigen::Isometry3d diving = MakeTransform({-50.0, 0.0, -10.0}, {0.0, DegToRad(90.0), 0.0});
  estimate = diving;
  estimate.translation().z() -= 0.5;
  e = ComputePoseError(diving, estimate);
  EXPECT_TRUE(e.position_m.isApprox(Eigen::Vector3d(0.5, 0.0, 0.0), 1e-12))
      << e.position_m.transpose();
  // Range from the truth only: 51 m away from the origin is region B regardless of the estimate.
  EXPECT_NEAR(e.range_m, std::sqrt(2600.0), 1e-12);
  EXPECT_EQ(e.region, Region::kB);
}

TEST(PoseError, OrientationErrorIsRelativeToTruth) {
  // Truth yawed 90 deg; the estimate rolled a further 3 deg about the receiver's own x axis.
  // In tanker axes that is a rotation about tanker y, yet the error must read as roll.
  const Eigen::Isometry3d truth = MakeTransform({-100.0, 0.0, -30.0}, {0.0, 0.0, DegToRad(90.0)});
  Eigen::Isometry3d estimate = truth;
  estimate.linear() = truth.linear() * Eigen::AngleAxisd(DegToRad(3.0), Eigen::Vector3d::UnitX());
  PoseError e = ComputePoseError(truth, estimate);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.roll), 3.0, 1e-9);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.pitch), 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.yaw), 0.0, 1e-9);
  EXPECT_EQ(e.region, Region::kA);

  // Hand-computed composite: yaw error 2 deg, then pitch error -1 deg about the new y.
  estimate.linear() =
      truth.linear() * RotationFromRollPitchYaw({0.0, DegToRad(-1.0), DegToRad(2.0)});
  e = ComputePoseError(truth, estimate);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.roll), 0.0, 1e-9);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.pitch), -1.0, 1e-9);
  EXPECT_NEAR(RadToDeg(e.orientation_rad.yaw), 2.0, 1e-9);
}

TEST(PoseError, SignsAreEstimateMinusTruth) {
  const Eigen::Isometry3d truth = MakeTransform({-40.0, 0.0, -15.0}, {0.0, 0.0, 0.0});
  const Eigen::Isometry3d estimate =
      MakeTransform({-40.2, 0.1, -14.95}, {0.0, 0.0, DegToRad(-0.5)});
  const PoseError e = ComputePoseError(truth, estimate);
  EXPECT_TRUE(e.position_m.isApprox(Eigen::Vector3d(-0.2, 0.1, 0.05), 1e-9));
  EXPECT_NEAR(RadToDeg(e.orientation_rad.yaw), -0.5, 1e-9);
}

TEST(Regions, Boundaries) {
  EXPECT_EQ(RegionOfRange(31.999), Region::kOutside);
  EXPECT_EQ(RegionOfRange(32.0), Region::kC);
  EXPECT_EQ(RegionOfRange(37.999), Region::kC);
  EXPECT_EQ(RegionOfRange(38.0), Region::kB);
  EXPECT_EQ(RegionOfRange(69.999), Region::kB);
  EXPECT_EQ(RegionOfRange(70.0), Region::kA);
  EXPECT_EQ(RegionOfRange(175.0), Region::kA);
  EXPECT_EQ(RegionOfRange(175.001), Region::kOutside);
  EXPECT_EQ(RegionOfRange(0.0), Region::kOutside);
  EXPECT_EQ(RegionOfRange(-50.0), Region::kOutside);
  EXPECT_EQ(RegionOfRange(std::numeric_limits<double>::quiet_NaN()), Region::kOutside);
  EXPECT_EQ(RegionOfRange(std::numeric_limits<double>::infinity()), Region::kOutside);
}

TEST(Regions, NamesAndMessageValues) {
  EXPECT_EQ(RegionName(Region::kA), "A");
  EXPECT_EQ(RegionName(Region::kB), "B");
  EXPECT_EQ(RegionName(Region::kC), "C");
  EXPECT_EQ(RegionName(Region::kOutside), "outside");
  // Same numbers as aar_msgs/PoseError's REGION_* constants.
  EXPECT_EQ(static_cast<int>(Region::kOutside), 0);
  EXPECT_EQ(static_cast<int>(Region::kA), 1);
  EXPECT_EQ(static_cast<int>(Region::kB), 2);
  EXPECT_EQ(static_cast<int>(Region::kC), 3);
}

TEST(Regions, CustomBounds) {
  RegionBounds bounds;
  bounds.a_max = 200.0;
  EXPECT_EQ(RegionOfRange(190.0, bounds), Region::kA);
}

}  // namespace
}  // namespace aar_geometry
