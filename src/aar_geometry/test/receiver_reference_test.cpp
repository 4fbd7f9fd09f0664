#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "aar_geometry/primitives.h"
#include "aar_geometry/receiver_reference.h"

namespace aar_geometry {
namespace {

TEST(ReceiverReference, CentroidSeed) {
  const std::vector<Eigen::Vector3d> reference = {{1, 0, 0}, {-1, 0, 0}, {0, 2, 0}, {0, -2, 2}};
  std::vector<Eigen::Vector3d> sensed;
  for (const auto& p : reference) sensed.push_back(p + Eigen::Vector3d(-35, 1, -10));
  const Eigen::Isometry3d seed = CentroidSeed(sensed, reference);
  EXPECT_TRUE(seed.linear().isIdentity());
  EXPECT_TRUE(seed.translation().isApprox(Eigen::Vector3d(-35, 1, -10)));
  EXPECT_THROW(CentroidSeed({}, reference), std::invalid_argument);
}

// Far clutter (a few hundred points scattered from 100 to 700 m, as block matching leaves of a
// textured background) drags the centroid tens of metres; the densest ball of the receiver's
// size keeps to the receiver.
TEST(ReceiverReference, DensestBallIgnoresFarClutter) {
  std::vector<Eigen::Vector3d> receiver, cloud;
  for (int i = 0; i < 2000; ++i)  // a 16 x 13 x 3 m box of points around (-35, 0, -10)
    receiver.push_back(Eigen::Vector3d(-35 + 6.5 * std::sin(i * 0.37), 8.0 * std::cos(i * 0.73),
                                       -10 + 1.5 * std::sin(i * 1.31)));
  cloud = receiver;
  for (int i = 0; i < 400; ++i) {  // clutter along the view, aft and down
    const double range = 100.0 + 600.0 * ((i * 37) % 400) / 400.0;
    cloud.push_back(
        Eigen::Vector3d(-20 - 0.9 * range, 40.0 * std::sin(i * 0.51), -3 - 0.42 * range));
  }
  const std::vector<Eigen::Vector3d> reference = receiver;  // centred like the sensed receiver
  const double radius = HalfDiagonal(reference);
  EXPECT_NEAR(radius, 0.5 * std::sqrt(13.0 * 13.0 + 16.0 * 16.0 + 3.0 * 3.0), 0.2);
  const Eigen::Vector3d truth = CentroidSeed(receiver, reference).translation();
  const double centroid_off = (CentroidSeed(cloud, reference).translation() - truth).norm();
  const std::vector<Eigen::Vector3d> ball = DensestBall(cloud, radius);
  const double ball_off = (CentroidSeed(ball, reference).translation() - truth).norm();
  std::printf("[ seed ] centroid %.1f m off, densest ball %.3f m off (%zu of %zu points)\n",
              centroid_off, ball_off, ball.size(), cloud.size());
  EXPECT_GT(centroid_off, 30.0);
  EXPECT_LT(ball_off, 0.5);
  EXPECT_EQ(ball.size(), receiver.size());      // nothing of the clutter within 10 m of it
  EXPECT_EQ(DensestBall(cloud, radius), ball);  // deterministic
  EXPECT_THROW(DensestBall({}, 1.0), std::invalid_argument);
  EXPECT_THROW(DensestBall(cloud, 0.0), std::invalid_argument);
}

TEST(ReceiverReference, ShellKeepsWhatTheEyesSee) {
  // A 2 m cube seen from far along +x: only the +x face is visible; adding an eye along +y keeps
  // only what both see (nothing: no face faces both).
  const TriangleMesh cube = MakeBox({2, 2, 2});
  ReferenceModelOptions o;
  o.points_per_m2 = 500;
  const ReferenceCloud dense = SampleReceiver(cube, o);
  const VisibilityTester tester(cube);
  const ReferenceCloud front = Shell(dense, tester, {{50, 0, 0}}, 0.005);
  EXPECT_NEAR(static_cast<double>(front.size()) / dense.size(), 1.0 / 6.0, 0.02);
  for (const auto& p : front.points) EXPECT_NEAR(p.x(), 1.0, 1e-9);
  EXPECT_EQ(Shell(dense, tester, {{50, 0, 0}, {0, 50, 0}}, 0.005).size(), 0u);
  // From a corner direction three faces are visible.
  const ReferenceCloud corner = Shell(dense, tester, {{50, 50, 50}}, 0.005);
  EXPECT_NEAR(static_cast<double>(corner.size()) / dense.size(), 0.5, 0.03);
}

// Finite but huge coordinates (a corrupt cloud, a pose placed by its centroid): Debian's Embree
// asserts on such rays and aborts the process. They are not cast; the rest are.
TEST(ReceiverReference, HugeCoordinatesAreNotCastAndDoNotAbort) {
  const TriangleMesh cube = MakeBox({2, 2, 2});
  const VisibilityTester tester(cube);
  const Eigen::Vector3d eye(50, 0, 0);
  const std::vector<Eigen::Vector3d> points = {
      {1, 0, 0}, {1e20, 0, 0}, {0, 0, 3e38}, {-1, 0, 0}, {1e10, 1e10, 0}};
  std::vector<Eigen::Vector3d> normals;  // facing the eye
  for (const auto& p : points) normals.push_back((eye - p).normalized());
  // From a sane eye the far points are cast (nothing in the way); the cube hides (-1, 0, 0).
  EXPECT_EQ(tester.Visible(points, normals, eye, 0.005),
            (std::vector<bool>{true, true, true, false, true}));
  // From an eye 1e20 m away (in the receiver frame when the pose is there) nothing is cast.
  EXPECT_EQ(tester.Visible(points, normals, Eigen::Vector3d(-1e20, 0, 0), 0.005),
            std::vector<bool>(points.size(), false));
  const std::vector<Eigen::Vector3d> origins = {{5, 0, 0}, {1e20, 0, 0}, {5, 0, 0}};
  const std::vector<Eigen::Vector3d> directions = {{-1, 0, 0}, {-1, 0, 0}, {1e20, 0, 0}};
  EXPECT_EQ(tester.RaysHit(origins, directions), (std::vector<bool>{true, false, false}));
}

}  // namespace
}  // namespace aar_geometry
