#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

struct SurfaceSamplingOptions {
  size_t num_points = 0;         // exact number of samples; 0: use points_per_m2
  double points_per_m2 = 400.0;  // [1/m^2] density when num_points is 0 (about 5 cm spacing)
  uint64_t seed = 1;             // same seed, same mesh: the same samples on every machine
};

// Points drawn uniformly over a mesh's surface (triangles chosen by area), each with the normal
// and part label of its triangle.
struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;   // [m], in the mesh frame
  std::vector<Eigen::Vector3d> normals;  // unit, from the triangle winding
  std::vector<int> parts;                // index into the mesh's part_names
  std::vector<int> triangles;            // the triangle each sample lies on

  size_t size() const { return points.size(); }
};

// Throws std::invalid_argument for a mesh with no area, or options that give fewer than one or
// more than 1e9 points.
SurfaceSamples SampleSurface(const TriangleMesh& mesh, const SurfaceSamplingOptions& options = {});

}  // namespace aar_geometry
