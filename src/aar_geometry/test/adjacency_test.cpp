#include "aar_geometry/adjacency.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "aar_geometry/primitives.h"
#include "aar_geometry/weld.h"
#include "test_files.h"

namespace aar_geometry {
namespace {

bool HasEdge(const std::vector<Edge>& edges, int a, int b) {
  const Edge e{std::min(a, b), std::max(a, b)};
  return std::find(edges.begin(), edges.end(), e) != edges.end();
}

TEST(Adjacency, ClosedCubeEveryTriangleHasThreeNeighbours) {
  const TriangleMesh cube = MakeBox({1.0, 1.0, 1.0});
  const TriangleAdjacency adjacency = BuildAdjacency(cube);
  ASSERT_EQ(adjacency.vertices.size(), 12u);
  EXPECT_TRUE(adjacency.open_edges.empty());
  EXPECT_TRUE(adjacency.nonmanifold_edges.empty());
  EXPECT_TRUE(adjacency.inconsistent_edges.empty());
  EXPECT_TRUE(adjacency.closed());
  for (int t = 0; t < 12; ++t) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(adjacency.vertices[t][k], cube.triangles[t][k]);
      const int n = adjacency.neighbors[t][k];
      ASSERT_GE(n, 0) << "triangle " << t << " edge " << k;
      ASSERT_NE(n, t);
      // The neighbour holds both vertices of the edge and points back across it.
      const int a = adjacency.vertices[t][k], b = adjacency.vertices[t][(k + 1) % 3];
      const auto& nv = adjacency.vertices[n];
      EXPECT_NE(std::find(nv.begin(), nv.end(), a), nv.end());
      EXPECT_NE(std::find(nv.begin(), nv.end(), b), nv.end());
      const auto& back = adjacency.neighbors[n];
      EXPECT_NE(std::find(back.begin(), back.end(), t), back.end());
    }
  }
}

TEST(Adjacency, OpenMeshReportsItsBoundary) {
  // Remove the cube's -z face (triangles 0 and 1, over vertices 0, 2, 3, 1): a box open at
  // the bottom, whose boundary is exactly that square.
  TriangleMesh open = MakeBox({1.0, 1.0, 1.0});
  open.triangles.erase(open.triangles.begin(), open.triangles.begin() + 2);
  open.triangle_parts.erase(open.triangle_parts.begin(), open.triangle_parts.begin() + 2);
  const TriangleAdjacency adjacency = BuildAdjacency(open);
  EXPECT_FALSE(adjacency.closed());
  ASSERT_EQ(adjacency.open_edges.size(), 4u);
  EXPECT_TRUE(HasEdge(adjacency.open_edges, 0, 2));
  EXPECT_TRUE(HasEdge(adjacency.open_edges, 2, 3));
  EXPECT_TRUE(HasEdge(adjacency.open_edges, 3, 1));
  EXPECT_TRUE(HasEdge(adjacency.open_edges, 1, 0));
  EXPECT_TRUE(adjacency.nonmanifold_edges.empty());
  int missing = 0;
  for (const auto& n : adjacency.neighbors)
    missing += static_cast<int>(std::count(n.begin(), n.end(), -1));
  EXPECT_EQ(missing, 4);
}

TEST(Adjacency, UnweldedMeshHasNoNeighbours) {
  const TriangleAdjacency adjacency = BuildAdjacency(test::UnsharedCube());
  EXPECT_EQ(adjacency.open_edges.size(), 36u);
  EXPECT_FALSE(adjacency.closed());
}

TEST(Adjacency, NonManifoldEdgeIsReported) {
  TriangleMesh fan;
  fan.AddPart("fan");
  fan.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};  // three triangles on edge 0-1
  fan.triangle_parts = {0, 0, 0};
  const TriangleAdjacency adjacency = BuildAdjacency(fan);
  ASSERT_EQ(adjacency.nonmanifold_edges.size(), 1u);
  EXPECT_TRUE(HasEdge(adjacency.nonmanifold_edges, 0, 1));
  EXPECT_EQ(adjacency.neighbors[0][0], -1);
  EXPECT_FALSE(adjacency.closed());
}

TEST(Adjacency, FlippedTriangleIsInconsistent) {
  TriangleMesh cube = MakeBox({1.0, 1.0, 1.0});
  std::swap(cube.triangles[5][1], cube.triangles[5][2]);
  const TriangleAdjacency adjacency = BuildAdjacency(cube);
  EXPECT_TRUE(adjacency.open_edges.empty());
  EXPECT_EQ(adjacency.inconsistent_edges.size(), 3u);
  EXPECT_FALSE(adjacency.closed());
}

TEST(Convexity, PrimitivesAreConvexAnLShapeIsNot) {
  EXPECT_TRUE(IsConvex(MakeBox({1.0, 2.0, 3.0})));
  EXPECT_TRUE(IsConvex(MakeCylinder(0.3, 2.0, 24)));
  EXPECT_TRUE(IsConvex(MakeSphere(0.5, 2)));
  TriangleMesh l_shape = MakeBox({2.0, 1.0, 1.0});
  l_shape.Append(MakeBox({1.0, 1.0, 2.0}), Eigen::Isometry3d(Eigen::Translation3d(0.5, 0.0, 1.0)));
  EXPECT_FALSE(IsConvex(l_shape));
  // Inside-out (inward normals): every other vertex is "outside" each face.
  TriangleMesh inverted = MakeBox({1.0, 1.0, 1.0});
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  EXPECT_FALSE(IsConvex(inverted));
}

TEST(Adjacency, DegenerateTrianglesHaveNoNeighboursAndOpenTheMesh) {
  TriangleMesh cube = MakeBox({1.0, 1.0, 1.0});
  cube.triangles.emplace_back(0, 0, 1);
  cube.triangle_parts.push_back(0);
  const TriangleAdjacency adjacency = BuildAdjacency(cube);
  EXPECT_EQ(adjacency.degenerate_triangles, std::vector<int>{12});
  EXPECT_EQ(adjacency.neighbors[12], (std::array<int, 3>{-1, -1, -1}));
  EXPECT_TRUE(adjacency.open_edges.empty());
  EXPECT_FALSE(adjacency.closed());
}

TEST(Convexity, FlatSurfacesAreNotConvex) {
  TriangleMesh sheet;  // a two-sided triangle: two faces enclose nothing
  sheet.AddPart("sheet");
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  sheet.triangle_parts = {0, 0};
  EXPECT_FALSE(BuildAdjacency(sheet).closed());
  EXPECT_EQ(BuildAdjacency(sheet).NotClosedReason(), "2 triangles, fewer than a tetrahedron's 4");
  EXPECT_FALSE(IsConvex(sheet));
  // A triangle against the fan of an inner point: four faces, every edge twice, opposite ways.
  TriangleMesh flat;
  flat.AddPart("flat");
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 0}};
  flat.triangles = {{0, 1, 2}, {1, 0, 3}, {2, 1, 3}, {0, 2, 3}};
  flat.triangle_parts = {0, 0, 0, 0};
  EXPECT_TRUE(BuildAdjacency(flat).closed());  // documented: closed() cannot see it
  EXPECT_FALSE(IsConvex(flat));
}

// A tetrahedron whose face (a, c, b) is split at m, the midpoint of a-b, with the zero-area
// triangle (a, m, b) closing the gap: every edge twice, opposite ways, yet one face has no normal.
TEST(Adjacency, ZeroAreaTriangleIsNotClosed) {
  TriangleMesh mesh;
  mesh.AddPart("tetra");
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0, 0}};  // a b c d m
  mesh.triangles = {{0, 2, 4}, {4, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 1}};
  mesh.triangle_parts.assign(6, 0);
  const TriangleAdjacency adjacency = BuildAdjacency(mesh);
  EXPECT_TRUE(adjacency.open_edges.empty());
  EXPECT_TRUE(adjacency.nonmanifold_edges.empty());
  EXPECT_TRUE(adjacency.inconsistent_edges.empty());
  EXPECT_TRUE(adjacency.degenerate_triangles.empty());
  EXPECT_EQ(adjacency.zero_area_triangles, std::vector<int>{5});
  EXPECT_FALSE(adjacency.closed());
  EXPECT_EQ(adjacency.NotClosedReason(), "1 zero-area triangle");
  // Three distinct indices at one point are zero-area too.
  mesh.vertices[4] = mesh.vertices[0];
  EXPECT_EQ(BuildAdjacency(mesh).zero_area_triangles, (std::vector<int>{0, 5}));
  // A sliver of real height is a triangle like any other.
  mesh.vertices[4] = {0.5, 0, 1e-6};
  EXPECT_TRUE(BuildAdjacency(mesh).zero_area_triangles.empty());
}

TEST(Adjacency, TooFewFacesAreNotClosed) {
  EXPECT_FALSE(BuildAdjacency(TriangleMesh()).closed());  // no edges at all: not a surface
  TriangleMesh one;  // what welding leaves of a one-triangle mesh with two equal corners
  one.AddPart("one");
  one.vertices = {{0, 0, 0}, {1, 0, 0}};
  one.triangles = {{0, 1, 1}};
  one.triangle_parts = {0};
  EXPECT_FALSE(BuildAdjacency(one).closed());
  EXPECT_EQ(BuildAdjacency(one).NotClosedReason(),
            "1 triangle with a repeated vertex, 0 triangles, fewer than a tetrahedron's 4");
  EXPECT_FALSE(BuildAdjacency(WeldVertices(one, 1e-4).mesh).closed());
  EXPECT_TRUE(BuildAdjacency(MakeBox({1.0, 1.0, 1.0})).closed());
  EXPECT_EQ(BuildAdjacency(MakeBox({1.0, 1.0, 1.0})).NotClosedReason(), "");
}

TEST(Adjacency, RejectsOutOfRangeIndices) {
  TriangleMesh bad = MakeBox({1.0, 1.0, 1.0});
  bad.triangles[0][2] = 99;
  EXPECT_THROW(BuildAdjacency(bad), std::invalid_argument);
  EXPECT_THROW(IsConvex(bad), std::invalid_argument);
  EXPECT_THROW(SelectParts(bad, {"box"}), std::invalid_argument);
  TriangleMesh short_labels = MakeBox({1.0, 1.0, 1.0});
  short_labels.triangle_parts.pop_back();
  TriangleMesh target;
  EXPECT_THROW(target.Append(short_labels), std::invalid_argument);
}

}  // namespace
}  // namespace aar_geometry
