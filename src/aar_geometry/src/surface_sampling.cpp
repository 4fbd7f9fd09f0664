#include "aar_geometry/surface_sampling.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace aar_geometry {
namespace {

// std::uniform_real_distribution differs between standard libraries; this mapping of the
// mt19937_64 stream does not, so a seed gives the same samples everywhere.
double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

SurfaceSamples SampleSurface(const TriangleMesh& mesh, const SurfaceSamplingOptions& options) {
  mesh.Validate();
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0.0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    total += mesh.TriangleArea(static_cast<int>(t));
    cumulative[t] = total;
  }
  if (!(total > 0.0)) throw std::invalid_argument("cannot sample a mesh with no surface area");
  if (options.num_points == 0 && !(options.points_per_m2 > 0.0)) {
    throw std::invalid_argument("sampling needs num_points > 0 or points_per_m2 > 0");
  }
  const double wanted = options.num_points > 0 ? static_cast<double>(options.num_points)
                                               : std::round(total * options.points_per_m2);
  if (!(wanted >= 1.0) || !(wanted <= 1e9)) {
    throw std::invalid_argument("sampling " + std::to_string(total) + " m^2 at " +
                                std::to_string(options.points_per_m2) + " points/m^2 gives " +
                                std::to_string(wanted) + " points: need 1 to 1e9");
  }
  const size_t count = static_cast<size_t>(wanted);

  std::mt19937_64 rng(options.seed);
  SurfaceSamples samples;
  samples.points.reserve(count);
  samples.normals.reserve(count);
  samples.parts.reserve(count);
  samples.triangles.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const double pick = Uniform01(rng) * total;
    const size_t t = std::min<size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        cumulative.size() - 1);
    // Uniform point in a triangle: sqrt warps the first coordinate so area, not edge, is uniform.
    const double r1 = std::sqrt(Uniform01(rng));
    const double r2 = Uniform01(rng);
    const Eigen::Vector3i& tri = mesh.triangles[t];
    samples.points.push_back((1.0 - r1) * mesh.vertices[tri[0]] +
                             r1 * (1.0 - r2) * mesh.vertices[tri[1]] +
                             r1 * r2 * mesh.vertices[tri[2]]);
    samples.normals.push_back(mesh.TriangleNormal(static_cast<int>(t)));
    samples.parts.push_back(mesh.triangle_parts[t]);
    samples.triangles.push_back(static_cast<int>(t));
  }
  return samples;
}

}  // namespace aar_geometry
