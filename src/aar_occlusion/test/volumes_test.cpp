#include "aar_occlusion/volumes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <aar_geometry/primitives.h>
#include <aar_geometry/weld.h>

namespace aar_occlusion {
namespace {

using aar_geometry::BuildAdjacency;
using aar_geometry::MakeBox;
using aar_geometry::TriangleMesh;

PartView View(const TriangleMesh& mesh, const Eigen::Vector3d& eye) {
  return ViewPart(mesh, BuildAdjacency(mesh), eye);
}

// True when `volume` has a plane equal to (normal, offset), normal given unnormalised.
bool HasPlane(const ConvexVolume& volume, const Eigen::Vector3d& normal, double offset) {
  const double scale = normal.norm();
  return std::any_of(volume.planes.begin(), volume.planes.end(), [&](const Plane& p) {
    return (p.normal - normal / scale).norm() < 1e-12 &&
           std::abs(p.offset - offset / scale) < 1e-12;
  });
}

TEST(Volumes, CubeSeenHeadOnByHand) {
  // Unit cube, eye 5 m along +x: only the +x face (2 triangles) faces it; its 4 edges are the
  // silhouette. The side plane through the eye and the top edge (z = 0.5) has normal
  // (0.5, 0, 4.5) ~ (1, 0, 9) and passes through the eye: offset 5 / sqrt(82).
  const TriangleMesh cube = MakeBox({1, 1, 1});
  const PartView v = View(cube, {5, 0, 0});
  EXPECT_EQ(std::count(v.facing.begin(), v.facing.end(), true), 2);
  EXPECT_EQ(v.silhouette.size(), 4u);
  ASSERT_EQ(v.cone.planes.size(), 4u);
  EXPECT_TRUE(HasPlane(v.cone, {1, 0, 9}, 5));
  EXPECT_TRUE(HasPlane(v.cone, {1, 0, -9}, 5));
  EXPECT_TRUE(HasPlane(v.cone, {1, 9, 0}, 5));
  EXPECT_TRUE(HasPlane(v.cone, {1, -9, 0}, 5));
  ASSERT_EQ(v.shadow.planes.size(), 6u);
  EXPECT_TRUE(HasPlane(v.shadow, {1, 0, 0}, 0.5));   // behind the +x face: x <= 0.5
  EXPECT_TRUE(HasPlane(v.light, {-1, 0, 0}, -0.5));  // in front of it: x >= 0.5

  EXPECT_TRUE(v.shadow.Contains({0, 0, 0}));      // the part itself
  EXPECT_TRUE(v.shadow.Contains({-3, 0.85, 0}));  // behind: the cone is 0.889 wide at x = -3
  EXPECT_FALSE(v.shadow.Contains({-3, 0.92, 0}));
  EXPECT_FALSE(v.shadow.Contains({1, 0, 0}));  // in front
  EXPECT_TRUE(v.light.Contains({1, 0, 0}));
  EXPECT_FALSE(v.light.Contains({6, 0, 0}));            // behind the eye: outside the cone
  EXPECT_TRUE(v.shadow.Contains({-3, 0.92, 0}, 0.05));  // grown by a margin
}

TEST(Volumes, TetrahedronByHand) {
  // Corner tetrahedron seen from (-1, -1, -1): the three faces through the origin face the eye,
  // the slanted face does not; the silhouette is the slanted face's three edges. Through the eye,
  // (1, 0, 0) and (0, 1, 0) the side plane is (1, 1, -3) / sqrt(11) with offset 1 / sqrt(11).
  TriangleMesh tet;
  tet.AddPart("tet");
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // outward
  tet.triangle_parts = {0, 0, 0, 0};
  const PartView v = View(tet, {-1, -1, -1});
  EXPECT_EQ(v.facing, (std::vector<bool>{true, true, true, false}));
  EXPECT_EQ(v.silhouette.size(), 3u);
  EXPECT_TRUE(HasPlane(v.cone, {1, 1, -3}, 1));
  EXPECT_TRUE(HasPlane(v.cone, {1, -3, 1}, 1));
  EXPECT_TRUE(HasPlane(v.cone, {-3, 1, 1}, 1));
  EXPECT_TRUE(HasPlane(v.shadow, {0, 0, -1}, 0));  // behind the z = 0 face: z >= 0
  EXPECT_TRUE(v.shadow.Contains({2, 2, 2}));       // along the ray through the centroid, beyond
  EXPECT_FALSE(v.shadow.Contains({-0.5, -0.5, -0.5}));
  EXPECT_TRUE(v.light.Contains({-0.5, -0.5, -0.5}));
}

TEST(Volumes, TwoEyesClassifyPoints) {
  // A 1 m cube 10 m ahead of eyes 2 m apart: just behind it, a point hides from both; farther
  // off-axis points hide from one eye only.
  const TriangleMesh cube = MakeBox({1, 1, 1});
  const ConvexVolume left = View(cube, {10, 1, 0}).shadow, right = View(cube, {10, -1, 0}).shadow;
  const auto c =
      Classify({{-0.6, 0, 0}, {-20, 2.5, 0}, {-20, -2.5, 0}, {-20, 8, 0}}, {left}, {right});
  EXPECT_EQ(c[0], Visibility::kNeither);
  EXPECT_EQ(c[1], Visibility::kLeftOnly);  // behind the cube as seen from the right eye
  EXPECT_EQ(c[2], Visibility::kRightOnly);
  EXPECT_EQ(c[3], Visibility::kBoth);
}

TEST(Volumes, TransformedVolumesMovePoints) {
  const TriangleMesh cube = MakeBox({1, 1, 1});
  const PartView v = View(cube, {5, 0, 0});
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
  T.translation() << -30, 2, -9;
  const ConvexVolume moved = v.shadow.Transformed(T);
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(-3, 0.85, 0), Eigen::Vector3d(-3, 0.92, 0), Eigen::Vector3d(1, 0, 0)}) {
    EXPECT_EQ(moved.Contains(T * p), v.shadow.Contains(p));
  }
}

TEST(Volumes, RefusesOpenNonConvexAndInsideEye) {
  TriangleMesh open = MakeBox({1, 1, 1});
  open.triangles.pop_back();
  open.triangle_parts.pop_back();
  try {
    View(open, {5, 0, 0});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is not closed"), std::string::npos) << e.what();
  }
  TriangleMesh l_shape = MakeBox({2, 1, 1});
  l_shape.Append(MakeBox({1, 1, 2}), Eigen::Isometry3d(Eigen::Translation3d(0.5, 0, 1)));
  const TriangleMesh welded = aar_geometry::WeldVertices(l_shape).mesh;
  EXPECT_THROW(View(welded, {5, 0, 0}), std::invalid_argument);
  EXPECT_THROW(View(MakeBox({1, 1, 1}), {0, 0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace aar_occlusion
