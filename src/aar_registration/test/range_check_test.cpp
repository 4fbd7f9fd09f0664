#include "aar_registration/range_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <aar_geometry/primitives.h>
#include <aar_geometry/receiver_reference.h>

namespace aar_registration {
namespace {

using aar_alignment::PinholeCamera;

// A receiver of boxes: fuselage 13 m, wings 16 m.
aar_geometry::TriangleMesh Receiver() {
  aar_geometry::TriangleMesh mesh;
  mesh.Append(aar_geometry::MakeBox({13.0, 1.6, 1.6}, "fuselage"));
  mesh.Append(aar_geometry::MakeBox({2.0, 16.0, 0.3}, "wing"),
              Eigen::Isometry3d(Eigen::Translation3d(1.0, 0.0, 0.0)));
  return mesh;
}

// The default rig's left camera (f 1108.5 px, b 0.5 m), looking straight aft: optical x along
// the tanker's -y, y along its z, z (the view) along its -x.
PinholeCamera LeftCamera() {
  PinholeCamera c;
  c.width = 1280, c.height = 960, c.fx = c.fy = 1108.5, c.cx = 639.5, c.cy = 479.5;
  c.T_tanker_optical.linear() << 0, 0, -1, -1, 0, 0, 0, 1, 0;
  c.T_tanker_optical.translation() = Eigen::Vector3d(-20.0, 0.25, -3.0);
  return c;
}

constexpr double kBaseline = 0.5;         // [m]
constexpr double kDisparitySigma = 0.25;  // [px]

// The receiver `depth` metres down the left camera's axis, at the tanker's attitude.
Eigen::Isometry3d ReceiverAt(double depth) {
  const PinholeCamera left = LeftCamera();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = left.T_tanker_optical * Eigen::Vector3d(0.0, 0.0, depth);
  return T;
}

// Stereo's points on the receiver at `T`: every `stride`th dense sample, each moved along its
// ray by stereo's range noise sigma_Z = Z^2 sigma_d / (f b).
std::vector<Eigen::Vector3d> Stereo(const Eigen::Isometry3d& T, int stride, unsigned seed) {
  const PinholeCamera left = LeftCamera();
  const Eigen::Vector3d eye = left.T_tanker_optical.translation();
  const auto dense =
      aar_geometry::SampleReceiver(Receiver(), aar_geometry::ReferenceModelOptions{});
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < dense.size(); i += stride) {
    const Eigen::Vector3d p = T * dense.points[i];
    const double z = (left.T_tanker_optical.inverse() * p).z();
    const double sigma = z * z * kDisparitySigma / (left.fx * kBaseline);
    points.push_back(eye + (p - eye) * (1.0 + sigma * unit(rng) / z));
  }
  return points;
}

RangeCheckOptions Options() {
  RangeCheckOptions o;
  o.sigmas = 3.0;
  o.disparity_sigma = kDisparitySigma;
  o.min_points = 10;
  return o;
}

RangeCheck Check(const std::vector<Eigen::Vector3d>& sensed, const Eigen::Isometry3d& T,
                 const std::vector<std::vector<Eigen::Vector3d>>& boom = {},
                 const RangeCheckOptions& options = Options()) {
  static const aar_alignment::OutlineModel model(Receiver());
  return CheckRange(sensed, model, LeftCamera(), kBaseline, boom, T, options);
}

TEST(RangeCheck, StereoAgreesWithTheRightRangeAndNotWithAWrongOne) {
  const std::vector<Eigen::Vector3d> sensed = Stereo(ReceiverAt(100.0), 40, 1);
  const RangeCheck right = Check(sensed, ReceiverAt(100.0));
  std::printf("[ right ] %s\n", right.ToString().c_str());
  ASSERT_TRUE(right.enough);
  EXPECT_TRUE(right.agrees);
  EXPECT_NEAR(right.median_depth, 100.0, 3.0);
  // 3 sigma_Z at 100 m: 3 * 100^2 * 0.25 / (1108.5 * 0.5) = 13.5 m.
  EXPECT_NEAR(right.tolerance, 13.5, 0.5);

  // The RQ-4's wrong start on suite approach 7003: 35 m too far at 101 m.
  const RangeCheck far = Check(sensed, ReceiverAt(135.0));
  std::printf("[ 35 m too far ] %s\n", far.ToString().c_str());
  ASSERT_TRUE(far.enough);
  EXPECT_FALSE(far.agrees);
  // And 25 m too near.
  const RangeCheck near = Check(sensed, ReceiverAt(75.0));
  ASSERT_TRUE(near.enough);
  EXPECT_FALSE(near.agrees);
}

// Far out one point's tolerance passes a wrong start: at 170 m, 3 sigma_Z = 3 * 170^2 * 0.25 /
// (1108.5 * 0.5) = 39 m, and the realistic world's two-rig start 32 m long (docs/AVAILABILITY.md)
// agreed. The median of the receiver's points is surer: counting 10 of them as independent, the
// tolerance is 39 / sqrt(10) = 12.3 m; the right range still agrees, the wrong one not.
TEST(RangeCheck, IndependentPointsNarrowTheToleranceFarOut) {
  const std::vector<Eigen::Vector3d> sensed = Stereo(ReceiverAt(170.0), 10, 4);
  const RangeCheck wide = Check(sensed, ReceiverAt(202.0));
  std::printf("[ one point's ] %s\n", wide.ToString().c_str());
  ASSERT_TRUE(wide.enough);
  EXPECT_NEAR(wide.tolerance, 39.1, 0.5);
  EXPECT_TRUE(wide.agrees);  // 32 m long passes

  RangeCheckOptions ten = Options();
  ten.independent_points = 10;
  const RangeCheck right = Check(sensed, ReceiverAt(170.0), {}, ten);
  std::printf("[ 10 independent, right ] %s\n", right.ToString().c_str());
  ASSERT_GE(right.points, 10);
  EXPECT_NEAR(right.tolerance, 39.1 / std::sqrt(10.0), 0.3);
  EXPECT_TRUE(right.agrees);
  const RangeCheck wrong = Check(sensed, ReceiverAt(202.0), {}, ten);
  std::printf("[ 10 independent, 32 m long ] %s\n", wrong.ToString().c_str());
  EXPECT_FALSE(wrong.agrees);
}

TEST(RangeCheck, TooFewPointsGiveNoVerdict) {
  const std::vector<Eigen::Vector3d> sensed = Stereo(ReceiverAt(100.0), 40, 2);
  const std::vector<Eigen::Vector3d> few(sensed.begin(), sensed.begin() + 5);
  const RangeCheck check = Check(few, ReceiverAt(100.0));
  EXPECT_EQ(check.points, 5);
  EXPECT_FALSE(check.enough);
  EXPECT_FALSE(check.agrees);
  EXPECT_NE(check.ToString().find("too few"), std::string::npos) << check.ToString();
  // Points off the receiver's image do not count: the receiver 30 m to one side.
  Eigen::Isometry3d aside = ReceiverAt(100.0);
  aside.translation() += LeftCamera().T_tanker_optical.linear() * Eigen::Vector3d(30.0, 0, 0);
  EXPECT_EQ(Check(sensed, aside).points, 0);
}

TEST(RangeCheck, TheBoomsLeftoverPointsInFrontAreSetAside) {
  const PinholeCamera left = LeftCamera();
  std::vector<Eigen::Vector3d> sensed = Stereo(ReceiverAt(100.0), 40, 3);
  const size_t receiver_points = sensed.size();
  const int on_image = Check(sensed, ReceiverAt(100.0)).points;  // the receiver's alone
  // Twice as many leftover points of a boom 12 m in front of the camera, on the receiver's image.
  std::vector<Eigen::Vector3d> boom_part;
  for (double z : {8.0, 12.0})
    for (double x : {-0.5, 0.5})
      for (double y : {-0.5, 0.5})
        boom_part.push_back(left.T_tanker_optical * Eigen::Vector3d(x, y, z));
  for (size_t i = 0; i < 2 * receiver_points; ++i)
    sensed.push_back(left.T_tanker_optical *
                     Eigen::Vector3d(0.01 * (i % 7), 0.01 * (i % 5), 10.0 + 0.001 * (i % 1000)));
  const RangeCheck with = Check(sensed, ReceiverAt(100.0), {boom_part});
  EXPECT_EQ(with.points, on_image);
  EXPECT_TRUE(with.agrees) << with.ToString();
  // Without the boom's description they outvote the receiver's.
  EXPECT_FALSE(Check(sensed, ReceiverAt(100.0)).agrees);
}

}  // namespace
}  // namespace aar_registration
