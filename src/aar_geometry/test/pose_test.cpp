#include "aar_geometry/pose.h"

#include <gtest/gtest.h>

#include <random>

namespace aar_geometry {
namespace {

TEST(Pose, IntrinsicZYXOrder) {
  // Yaw 90 deg, then pitch 90 deg about the new y; by hand from R = Rz(90) * Ry(90): body x
  // points down (-z), body y along -x, body z along +y.
  const Eigen::Matrix3d R = RotationFromRollPitchYaw({0.0, DegToRad(90.0), DegToRad(90.0)});
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_TRUE((R * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));

  // Positive roll lifts the left wing (+y): right wing down, by the right-hand rule about x.
  const Eigen::Matrix3d roll = RotationFromRollPitchYaw({DegToRad(30.0), 0.0, 0.0});
  EXPECT_TRUE(
      (roll * Eigen::Vector3d::UnitY())
          .isApprox(Eigen::Vector3d(0.0, std::cos(DegToRad(30.0)), std::sin(DegToRad(30.0))),
                    1e-12));
  // Positive pitch puts the nose (+x) down in REP-103.
  const Eigen::Matrix3d pitch = RotationFromRollPitchYaw({0.0, DegToRad(10.0), 0.0});
  EXPECT_LT((pitch * Eigen::Vector3d::UnitX()).z(), 0.0);
}

void ExpectRoundTrip(const RollPitchYaw& in) {
  const RollPitchYaw out = RollPitchYawFromRotation(RotationFromRollPitchYaw(in));
  EXPECT_NEAR(out.roll, in.roll, 1e-9);
  EXPECT_NEAR(out.pitch, in.pitch, 1e-9);
  EXPECT_NEAR(out.yaw, in.yaw, 1e-9);
}

TEST(Pose, RoundTripsAwayFromGimbalLock) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-M_PI + 1e-6, M_PI);
  std::uniform_real_distribution<double> pitch(-M_PI / 2 + 1e-3, M_PI / 2 - 1e-3);
  for (int i = 0; i < 1000; ++i) ExpectRoundTrip({angle(rng), pitch(rng), angle(rng)});
  ExpectRoundTrip({0.0, 0.0, 0.0});
  ExpectRoundTrip({DegToRad(2.0), DegToRad(-3.0), DegToRad(179.0)});
}

TEST(Pose, RoundTripsNearPlusMinusNinetyPitch) {
  for (double deg : {89.0, 89.9, 89.99, 89.999, -89.0, -89.99, -89.999}) {
    SCOPED_TRACE(deg);
    const RollPitchYaw in{DegToRad(12.0), DegToRad(deg), DegToRad(-40.0)};
    const RollPitchYaw out = RollPitchYawFromRotation(RotationFromRollPitchYaw(in));
    EXPECT_NEAR(out.pitch, in.pitch, 1e-9);
    // Near the lock roll and yaw lose precision as eps / cos(pitch): at 89.999 deg both they and
    // the rebuilt rotation were measured within 1e-11.
    EXPECT_LT((RotationFromRollPitchYaw(out) - RotationFromRollPitchYaw(in)).norm(), 1e-10);
    EXPECT_NEAR(out.roll, in.roll, 1e-9);
    EXPECT_NEAR(out.yaw, in.yaw, 1e-9);
  }
}

TEST(Pose, ExactlyNinetyPitchRebuildsTheRotation) {
  for (double deg : {90.0, -90.0}) {
    SCOPED_TRACE(deg);
    const RollPitchYaw in{DegToRad(25.0), DegToRad(deg), DegToRad(60.0)};
    const Eigen::Matrix3d R = RotationFromRollPitchYaw(in);
    const RollPitchYaw out = RollPitchYawFromRotation(R);
    EXPECT_NEAR(out.pitch, in.pitch, 1e-9);
    EXPECT_EQ(out.roll, 0.0);
    EXPECT_TRUE(RotationFromRollPitchYaw(out).isApprox(R, 1e-12));
  }
}

TEST(Pose, OpticalFrameConvention) {
  const Eigen::Matrix3d R = R_body_optical();
  EXPECT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));   // forward
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));  // right
  EXPECT_TRUE((R * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));  // down
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  // The transform carries the same rotation and no offset; tf's static_transform_publisher
  // quaternion for it is (x, y, z, w) = (-0.5, 0.5, -0.5, 0.5).
  EXPECT_EQ(T_body_optical().linear(), R);
  EXPECT_EQ(T_body_optical().translation(), Eigen::Vector3d::Zero());
  const Eigen::Quaterniond q(R);
  const Eigen::Vector4d expected(-0.5, 0.5, -0.5, 0.5);
  EXPECT_TRUE(q.coeffs().isApprox(expected) || q.coeffs().isApprox(-expected))
      << q.coeffs().transpose();
  // REP-103's optical frame is roll -90, pitch 0, yaw -90 from the body frame.
  EXPECT_TRUE(RotationFromRollPitchYaw({DegToRad(-90.0), 0.0, DegToRad(-90.0)}).isApprox(R, 1e-12));
}

TEST(Pose, AnglesStayInRangeAndReflectionsAreRejected) {
  // Yaw of exactly 180 deg: atan2 of a -0.0 sine would say -180.
  Eigen::Matrix3d R = RotationFromRollPitchYaw({0.0, 0.0, M_PI});
  R(1, 0) = -0.0;
  EXPECT_EQ(RollPitchYawFromRotation(R).yaw, M_PI);
  Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
  mirror(1, 1) = -1.0;
  EXPECT_THROW(RollPitchYawFromRotation(mirror), std::invalid_argument);
  EXPECT_THROW(RollPitchYawFromRotation(2.0 * Eigen::Matrix3d::Identity()), std::invalid_argument);
}

TEST(Pose, MakeTransformPlacesAndTurns) {
  const Eigen::Isometry3d T = MakeTransform({-35.0, 0.0, -8.0}, {0.0, 0.0, DegToRad(90.0)});
  EXPECT_TRUE((T * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(-35.0, 1.0, -8.0)));
}

TEST(Pose, ExtrapolateMovesOnAtConstantVelocity) {
  const Eigen::Isometry3d T = MakeTransform({-50.0, 1.0, -10.0}, {0.01, -0.02, 0.3});
  const Eigen::Vector3d v(2.0, -0.5, 0.25), w(0.0, 0.0, 0.1);
  const Eigen::Isometry3d T1 = ExtrapolatePose(T, v, w, 0.5);
  EXPECT_TRUE(T1.translation().isApprox(T.translation() + 0.5 * v, 1e-12));
  // A turn about the parent's z by 0.05 rad: yaw grows by that, roll and pitch about z stay.
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()) * T.linear();
  EXPECT_TRUE(T1.linear().isApprox(expected, 1e-12));
  // Back by the same time is the inverse step; zero rates and zero time change nothing.
  EXPECT_TRUE(ExtrapolatePose(T1, v, w, -0.5).isApprox(T, 1e-12));
  EXPECT_TRUE(
      ExtrapolatePose(T, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 3.0).isApprox(T));
  EXPECT_TRUE(ExtrapolatePose(T, v, w, 0.0).isApprox(T));
}

}  // namespace
}  // namespace aar_geometry
