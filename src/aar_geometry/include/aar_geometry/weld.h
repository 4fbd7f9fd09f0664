#pragma once

#include <cstddef>
#include <vector>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

struct WeldResult {
  TriangleMesh mesh;             // welded mesh, degenerate triangles removed
  std::vector<int> old_to_new;   // input vertex index -> output vertex index
  size_t merged_vertices = 0;    // input vertices folded into an earlier one
  size_t removed_triangles = 0;  // triangles left with fewer than three distinct vertices
};

// Merges vertices that lie within `epsilon` of each other in every coordinate (the thesis's
// 1e-4 m per x, y, z), so that triangles that touch share vertex indices and adjacency can be
// computed. Each vertex joins the first kept vertex within epsilon (not the nearest, and not
// transitively: with A, B = A + 0.9 eps and C = A + 1.5 eps, C stays apart). Expected O(n)
// through a hash grid. Throws std::invalid_argument for epsilon <= 0 or one so small against the
// coordinates that grid cells cannot be numbered exactly.
WeldResult WeldVertices(const TriangleMesh& mesh, double epsilon = 1e-4);

}  // namespace aar_geometry
