#include "aar_description/loft.h"

#include <cmath>
#include <stdexcept>

namespace aar_description {
namespace {

Eigen::Vector3d Centroid(const Ring& ring) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : ring) c += p;
  return c / static_cast<double>(ring.size());
}

// Adds triangle (a, b, c), flipped if its normal points against `outward`.
void AddOriented(aar_geometry::TriangleMesh& mesh, int part, int a, int b, int c,
                 const Eigen::Vector3d& outward) {
  const Eigen::Vector3d n =
      (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
  if (n.squaredNorm() == 0.0) return;  // degenerate (a collapsed ring point)
  if (n.dot(outward) < 0.0) std::swap(b, c);
  mesh.triangles.emplace_back(a, b, c);
  mesh.triangle_parts.push_back(part);
}

}  // namespace

void AppendLoft(aar_geometry::TriangleMesh& mesh, const std::string& part_name,
                const std::vector<Ring>& rings, bool cap_first, bool cap_last) {
  if (rings.size() < 2) throw std::invalid_argument("a loft needs at least two rings");
  const size_t n = rings.front().size();
  for (const auto& ring : rings) {
    if (ring.size() != n || n < 3) throw std::invalid_argument("loft rings differ in size");
  }
  const int part = mesh.AddPart(part_name);
  const int base = static_cast<int>(mesh.vertices.size());
  for (const auto& ring : rings)
    mesh.vertices.insert(mesh.vertices.end(), ring.begin(), ring.end());
  auto index = [&](size_t r, size_t k) { return base + static_cast<int>(r * n + k % n); };

  for (size_t r = 0; r + 1 < rings.size(); ++r) {
    const Eigen::Vector3d axis_point = 0.5 * (Centroid(rings[r]) + Centroid(rings[r + 1]));
    for (size_t k = 0; k < n; ++k) {
      const int a = index(r, k), b = index(r, k + 1), c = index(r + 1, k + 1), d = index(r + 1, k);
      const Eigen::Vector3d mid =
          0.25 * (mesh.vertices[a] + mesh.vertices[b] + mesh.vertices[c] + mesh.vertices[d]);
      AddOriented(mesh, part, a, b, c, mid - axis_point);
      AddOriented(mesh, part, a, c, d, mid - axis_point);
    }
  }
  auto cap = [&](size_t r, const Eigen::Vector3d& outward) {
    const int centre = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(Centroid(rings[r]));
    for (size_t k = 0; k < n; ++k)
      AddOriented(mesh, part, centre, index(r, k), index(r, k + 1), outward);
  };
  const Eigen::Vector3d direction = Centroid(rings.back()) - Centroid(rings.front());
  if (cap_first) cap(0, -direction);
  if (cap_last) cap(rings.size() - 1, direction);
}

Ring SuperellipseRing(double x0, double y0, double z0, double a, double b, double exponent,
                      int segments) {
  Ring ring;
  ring.reserve(segments);
  for (int i = 0; i < segments; ++i) {
    const double t = 2.0 * M_PI * i / segments;
    const double c = std::cos(t), s = std::sin(t);
    const double e = 2.0 / exponent;
    ring.emplace_back(x0, y0 + a * std::copysign(std::pow(std::abs(c), e), c),
                      z0 + b * std::copysign(std::pow(std::abs(s), e), s));
  }
  return ring;
}

std::vector<Eigen::Vector2d> AirfoilSection(double chord, double thickness_ratio, int points) {
  auto half_thickness = [&](double u) {
    return 5.0 * thickness_ratio *
           (0.2969 * std::sqrt(u) - 0.1260 * u - 0.3516 * u * u + 0.2843 * u * u * u -
            0.1036 * u * u * u * u);
  };
  std::vector<Eigen::Vector2d> section;
  // Upper surface trailing edge -> leading edge, then lower surface leading -> trailing edge,
  // cosine-spaced so the rounded leading edge gets the points.
  for (int i = points; i >= 0; --i) {
    const double u = 0.5 * (1.0 - std::cos(M_PI * i / points));
    section.emplace_back(u * chord, half_thickness(u) * chord);
  }
  for (int i = 1; i < points; ++i) {
    const double u = 0.5 * (1.0 - std::cos(M_PI * i / points));
    section.emplace_back(u * chord, -half_thickness(u) * chord);
  }
  return section;
}

}  // namespace aar_description
