#include "aar_geometry/weld.h"

#include <gtest/gtest.h>

#include "aar_geometry/adjacency.h"
#include "aar_geometry/mesh_io.h"
#include "test_files.h"

namespace aar_geometry {
namespace {

TEST(Weld, StlCubeBecomesClosedWithEightVertices) {
  const TriangleMesh stl = LoadMesh(test::DataPath("cube.stl"));
  ASSERT_EQ(stl.triangles.size(), 12u);
  ASSERT_EQ(stl.vertices.size(), 36u);  // STL stores each facet's corners on their own
  EXPECT_FALSE(BuildAdjacency(stl).closed());

  const WeldResult welded = WeldVertices(stl);
  EXPECT_EQ(welded.mesh.vertices.size(), 8u);
  EXPECT_EQ(welded.merged_vertices, 28u);
  EXPECT_EQ(welded.removed_triangles, 0u);
  EXPECT_EQ(welded.mesh.triangles.size(), 12u);
  EXPECT_TRUE(BuildAdjacency(welded.mesh).closed());
  for (size_t i = 0; i < stl.vertices.size(); ++i) {
    EXPECT_TRUE(welded.mesh.vertices[welded.old_to_new[i]].isApprox(stl.vertices[i]));
  }
}

TriangleMesh TwoTriangles(const Eigen::Vector3d& offset) {
  // Two triangles whose shared corner is stored twice, the second copy displaced by `offset`.
  TriangleMesh mesh;
  mesh.AddPart("p");
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, Eigen::Vector3d(1, 0, 0) + offset,
                   {1, 1, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  mesh.triangle_parts = {0, 0};
  return mesh;
}

TEST(Weld, ToleranceIsPerAxis) {
  // 0.9e-4 m in every axis is 1.56e-4 m apart, yet within the thesis's 1e-4 m per component.
  EXPECT_EQ(WeldVertices(TwoTriangles({0.9e-4, 0.9e-4, 0.9e-4})).mesh.vertices.size(), 4u);
  EXPECT_EQ(WeldVertices(TwoTriangles({1.1e-4, 0.0, 0.0})).mesh.vertices.size(), 5u);
  EXPECT_EQ(WeldVertices(TwoTriangles({0.0, 0.0, -1.1e-4})).mesh.vertices.size(), 5u);
  EXPECT_EQ(WeldVertices(TwoTriangles({1.1e-4, 0.0, 0.0}), 2e-4).mesh.vertices.size(), 4u);
}

TEST(Weld, MergesAcrossGridCellBoundaries) {
  // Vertices on either side of a multiple of epsilon fall in different hash cells.
  TriangleMesh mesh = TwoTriangles({0.0, 0.0, 0.0});
  mesh.vertices[1] = {0.99999e-4 * 1000.0, 0.0, 0.0};
  mesh.vertices[3] = {1.00001e-4 * 1000.0, 0.0, 0.0};
  const WeldResult welded = WeldVertices(mesh, 1e-4);
  EXPECT_EQ(welded.mesh.vertices.size(), 4u);
  EXPECT_EQ(welded.old_to_new[3], welded.old_to_new[1]);
}

TEST(Weld, DropsTrianglesThatCollapse) {
  TriangleMesh mesh = TwoTriangles({0.0, 0.0, 0.0});
  mesh.vertices[4] = {1.0, 0.5e-4, 0.0};  // collapses onto vertex 3 (== vertex 1)
  const WeldResult welded = WeldVertices(mesh);
  EXPECT_EQ(welded.removed_triangles, 1u);
  EXPECT_EQ(welded.mesh.triangles.size(), 1u);
  EXPECT_EQ(welded.mesh.triangle_parts.size(), 1u);
}

TEST(Weld, KeepsPartLabels) {
  TriangleMesh mesh = TwoTriangles({0.0, 0.0, 0.0});
  mesh.AddPart("q");
  mesh.triangle_parts = {0, 1};
  const WeldResult welded = WeldVertices(mesh);
  EXPECT_EQ(welded.mesh.part_names, (std::vector<std::string>{"p", "q"}));
  EXPECT_EQ(welded.mesh.triangle_parts, (std::vector<int>{0, 1}));
}

TEST(Weld, FarFromTheOriginStaysCorrect) {
  // 3000 km out: cell numbers beyond 32 bits.
  TriangleMesh mesh = TwoTriangles({0.5e-4, 0.0, 0.0});
  for (auto& v : mesh.vertices) v += Eigen::Vector3d(3e6, -3e6, 1e6);
  EXPECT_EQ(WeldVertices(mesh).mesh.vertices.size(), 4u);
  // An epsilon too small to number the cells exactly is refused, not mis-welded.
  EXPECT_THROW(WeldVertices(mesh, 1e-12), std::invalid_argument);
}

TEST(Weld, RejectsBadEpsilon) {
  EXPECT_THROW(WeldVertices(TwoTriangles({0, 0, 0}), 0.0), std::invalid_argument);
  EXPECT_THROW(WeldVertices(TwoTriangles({0, 0, 0}), std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace aar_geometry
