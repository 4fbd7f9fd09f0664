#include "aar_geometry/weld.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

namespace aar_geometry {
namespace {

using Cell = Eigen::Matrix<int64_t, 3, 1>;

struct CellHash {
  size_t operator()(const Cell& c) const {
    // Large primes spread neighbouring cells over the table.
    return static_cast<size_t>(c.x()) * 73856093u ^ static_cast<size_t>(c.y()) * 19349663u ^
           static_cast<size_t>(c.z()) * 83492791u;
  }
};

struct CellEqual {
  bool operator()(const Cell& a, const Cell& b) const { return a == b; }
};

}  // namespace

WeldResult WeldVertices(const TriangleMesh& mesh, double epsilon) {
  if (!(epsilon > 0.0)) throw std::invalid_argument("weld epsilon must be positive");
  mesh.Validate();

  WeldResult result;
  result.mesh.part_names = mesh.part_names;
  result.old_to_new.resize(mesh.vertices.size());

  // Cells of size epsilon: any vertex within epsilon per axis sits in the same or an adjacent cell.
  std::unordered_multimap<Cell, int, CellHash, CellEqual> grid;
  grid.reserve(mesh.vertices.size());
  double extent = 0.0;
  for (const auto& v : mesh.vertices) extent = std::max(extent, v.cwiseAbs().maxCoeff());
  if (extent / epsilon > 1e15) {  // cell numbers must stay exact in double and int64
    throw std::invalid_argument("weld epsilon " + std::to_string(epsilon) +
                                " m is too small for coordinates up to " + std::to_string(extent) +
                                " m");
  }
  auto cell_of = [epsilon](const Eigen::Vector3d& v) {
    return Cell(static_cast<int64_t>(std::floor(v.x() / epsilon)),
                static_cast<int64_t>(std::floor(v.y() / epsilon)),
                static_cast<int64_t>(std::floor(v.z() / epsilon)));
  };
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& v = mesh.vertices[i];
    const Cell cell = cell_of(v);
    int match = -1;
    for (int dx = -1; dx <= 1 && match < 0; ++dx) {
      for (int dy = -1; dy <= 1 && match < 0; ++dy) {
        for (int dz = -1; dz <= 1 && match < 0; ++dz) {
          auto range = grid.equal_range(Cell(cell + Cell(dx, dy, dz)));
          for (auto it = range.first; it != range.second; ++it) {
            if ((result.mesh.vertices[it->second] - v).cwiseAbs().maxCoeff() <= epsilon) {
              match = it->second;
              break;
            }
          }
        }
      }
    }
    if (match >= 0) {
      result.old_to_new[i] = match;
      ++result.merged_vertices;
    } else {
      const int index = static_cast<int>(result.mesh.vertices.size());
      result.mesh.vertices.push_back(v);
      grid.emplace(cell, index);
      result.old_to_new[i] = index;
    }
  }

  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i tri(result.old_to_new[mesh.triangles[t][0]],
                              result.old_to_new[mesh.triangles[t][1]],
                              result.old_to_new[mesh.triangles[t][2]]);
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      ++result.removed_triangles;
      continue;
    }
    result.mesh.triangles.push_back(tri);
    result.mesh.triangle_parts.push_back(mesh.triangle_parts[t]);
  }
  return result;
}

}  // namespace aar_geometry
