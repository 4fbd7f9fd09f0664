#include "aar_geometry/primitives.h"

#include <gtest/gtest.h>

#include <limits>

#include "aar_geometry/adjacency.h"

namespace aar_geometry {
namespace {

// Every triangle's normal points away from the centre of a convex primitive at the origin.
void ExpectOutwardNormals(const TriangleMesh& mesh) {
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d centroid =
        (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
    EXPECT_GT(mesh.TriangleNormal(static_cast<int>(t)).dot(centroid), 0.0) << "triangle " << t;
  }
}

TEST(Primitives, BoxIsClosedOutwardAndSized) {
  const TriangleMesh box = MakeBox({2.0, 1.0, 0.5}, "ruddevator");
  EXPECT_EQ(box.vertices.size(), 8u);
  EXPECT_EQ(box.triangles.size(), 12u);
  EXPECT_EQ(box.part_names, std::vector<std::string>{"ruddevator"});
  EXPECT_TRUE(BuildAdjacency(box).closed());
  ExpectOutwardNormals(box);
  EXPECT_NEAR(box.SurfaceArea(), 2.0 * (2.0 * 1.0 + 1.0 * 0.5 + 0.5 * 2.0), 1e-12);
  EXPECT_TRUE(box.Bounds().max().isApprox(Eigen::Vector3d(1.0, 0.5, 0.25)));
}

TEST(Primitives, CylinderAlongZIsClosedAndOutward) {
  const TriangleMesh cylinder = MakeCylinder(0.25, 8.0, 64);
  EXPECT_EQ(cylinder.triangles.size(), 4u * 64u);
  EXPECT_TRUE(BuildAdjacency(cylinder).closed());
  ExpectOutwardNormals(cylinder);
  EXPECT_NEAR(cylinder.Bounds().max().z(), 4.0, 1e-12);
  EXPECT_NEAR(cylinder.Bounds().min().z(), -4.0, 1e-12);
  const double exact = 2.0 * M_PI * 0.25 * 8.0 + 2.0 * M_PI * 0.25 * 0.25;
  EXPECT_NEAR(cylinder.SurfaceArea(), exact, 0.01 * exact);  // inscribed polygon: ~0.2% low
}

TEST(Primitives, SphereIsClosedOutwardAndRound) {
  const TriangleMesh sphere = MakeSphere(0.15, 3);
  EXPECT_EQ(sphere.triangles.size(), 20u * 64u);
  EXPECT_TRUE(BuildAdjacency(sphere).closed());
  ExpectOutwardNormals(sphere);
  for (const auto& v : sphere.vertices) EXPECT_NEAR(v.norm(), 0.15, 1e-12);
  const double exact = 4.0 * M_PI * 0.15 * 0.15;
  EXPECT_NEAR(sphere.SurfaceArea(), exact, 0.02 * exact);
}

TEST(Primitives, RejectNonsenseSizes) {
  EXPECT_THROW(MakeBox({1.0, 0.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(MakeCylinder(-1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(MakeCylinder(1.0, 1.0, 2), std::invalid_argument);
  EXPECT_THROW(MakeSphere(std::nan(""), 1), std::invalid_argument);
  EXPECT_THROW(MakeBox({1.0, std::numeric_limits<double>::infinity(), 1.0}), std::invalid_argument);
  EXPECT_THROW(MakeCylinder(std::numeric_limits<double>::infinity(), 1.0), std::invalid_argument);
}

// Normals point out after a mirror, whether through Transformed, Append or Scaled.
TEST(Primitives, MirrorsKeepNormalsOutward) {
  Eigen::Isometry3d mirror = Eigen::Isometry3d::Identity();
  mirror.linear()(1, 1) = -1.0;
  mirror.translation() << 5.0, 0.0, 0.0;
  const TriangleMesh box = MakeBox({1.0, 2.0, 3.0});
  TriangleMesh appended;
  appended.Append(box, mirror);
  for (const TriangleMesh& m :
       {Transformed(box, mirror), appended, Scaled(box, {1.0, -1.0, 1.0})}) {
    const Eigen::Vector3d centre = m.Bounds().center();
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      const Eigen::Vector3d c =
          (m.vertices[tri[0]] + m.vertices[tri[1]] + m.vertices[tri[2]]) / 3.0;
      EXPECT_GT(m.TriangleNormal(static_cast<int>(t)).dot(c - centre), 0.0);
    }
  }
  EXPECT_THROW(Scaled(box, {1.0, 0.0, 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace aar_geometry
