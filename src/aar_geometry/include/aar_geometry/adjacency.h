#pragma once

#include <array>
#include <string>
#include <vector>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// An undirected edge between two vertex indices, v0 < v1.
struct Edge {
  int v0 = -1;
  int v1 = -1;
  bool operator==(const Edge& o) const { return v0 == o.v0 && v1 == o.v1; }
};

// Zero to rounding: a triangle's height below 1e-12 of its longest edge.
constexpr double kZeroAreaRatio = 1e-12;

// Winged-triangle adjacency (thesis 3.8): each triangle knows its three vertices and, across
// each of its edges, its neighbour. Edge k of triangle t runs from vertices[t][k] to
// vertices[t][(k + 1) % 3]; neighbors[t][k] is the triangle across it, or -1 when the edge is
// open or shared by more than two triangles.
struct TriangleAdjacency {
  std::vector<std::array<int, 3>> vertices;
  std::vector<std::array<int, 3>> neighbors;
  std::vector<Edge> open_edges;           // used by one triangle: the boundary of an open mesh
  std::vector<Edge> nonmanifold_edges;    // used by three or more triangles
  std::vector<Edge> inconsistent_edges;   // two triangles that run the edge the same way (flipped)
  std::vector<int> degenerate_triangles;  // a repeated vertex index: no edges, no neighbours
  // Three distinct vertices on a line (twice the area at most kZeroAreaRatio x the longest edge
  // squared): edges and neighbours as any triangle, but no normal to wind or extrude.
  std::vector<int> zero_area_triangles;

  // Watertight and consistently wound, with a normal on every triangle and at least the four
  // faces of a tetrahedron: the precondition of silhouettes and shadow volumes. (A two-sided
  // sheet, each triangle doubled with the opposite winding, also passes: it encloses no volume;
  // IsConvex rejects it.)
  bool closed() const {
    return vertices.size() >= degenerate_triangles.size() + 4 && open_edges.empty() &&
           nonmanifold_edges.empty() && inconsistent_edges.empty() &&
           degenerate_triangles.empty() && zero_area_triangles.empty();
  }
  // Why closed() is false, e.g. "4 open edges, 1 zero-area triangle"; empty when closed.
  std::string NotClosedReason() const;
};

// Adjacency by shared vertex indices: weld the mesh first (WeldVertices) when its triangles do
// not share vertices.
TriangleAdjacency BuildAdjacency(const TriangleMesh& mesh);

// True when no vertex lies more than `tolerance` [m] outside the plane of any non-degenerate
// triangle: for a closed, outward-wound mesh, that it bounds a convex volume (what point
// inclusion by planes needs). O(triangles x vertices): meant for the dozen-part collision models.
// Throws std::invalid_argument for a malformed mesh.
bool IsConvex(const TriangleMesh& mesh, double tolerance = 1e-6);

}  // namespace aar_geometry
