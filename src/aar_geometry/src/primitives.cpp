#include "aar_geometry/primitives.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace aar_geometry {
namespace {

TriangleMesh OnePart(const std::string& part) {
  TriangleMesh mesh;
  mesh.AddPart(part);
  return mesh;
}

void AddTriangle(TriangleMesh& mesh, int a, int b, int c) {
  mesh.triangles.emplace_back(a, b, c);
  mesh.triangle_parts.push_back(0);
}

}  // namespace

TriangleMesh MakeBox(const Eigen::Vector3d& size, const std::string& part) {
  if (!(size.array() > 0.0).all() || !size.allFinite()) {
    throw std::invalid_argument("box size must be positive and finite");
  }
  TriangleMesh mesh = OnePart(part);
  const Eigen::Vector3d h = 0.5 * size;
  // Vertex i has x = bit0, y = bit1, z = bit2 (0 -> -h, 1 -> +h).
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                               (i & 4) ? h.z() : -h.z());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 2, 3, 1},   // -z
                           {4, 5, 7, 6},   // +z
                           {0, 1, 5, 4},   // -y
                           {2, 6, 7, 3},   // +y
                           {0, 4, 6, 2},   // -x
                           {1, 3, 7, 5}};  // +x
  for (const auto& f : faces) {
    AddTriangle(mesh, f[0], f[1], f[2]);
    AddTriangle(mesh, f[0], f[2], f[3]);
  }
  return mesh;
}

TriangleMesh MakeCylinder(double radius, double length, int segments, const std::string& part) {
  if (!(radius > 0.0) || !(length > 0.0) || !std::isfinite(radius) || !std::isfinite(length)) {
    throw std::invalid_argument("cylinder radius and length must be positive and finite");
  }
  if (segments < 3) throw std::invalid_argument("cylinder needs at least 3 segments");
  TriangleMesh mesh = OnePart(part);
  const double half = 0.5 * length;
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * M_PI * i / segments;
    mesh.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), -half);
    mesh.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), half);
  }
  const int bottom_centre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0.0, 0.0, -half);
  const int top_centre = bottom_centre + 1;
  mesh.vertices.emplace_back(0.0, 0.0, half);
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    const int b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * j, t1 = 2 * j + 1;
    AddTriangle(mesh, b0, b1, t1);
    AddTriangle(mesh, b0, t1, t0);
    AddTriangle(mesh, bottom_centre, b1, b0);
    AddTriangle(mesh, top_centre, t0, t1);
  }
  return mesh;
}

TriangleMesh MakeSphere(double radius, int subdivisions, const std::string& part) {
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw std::invalid_argument("sphere radius must be positive and finite");
  }
  if (subdivisions < 0 || subdivisions > 6) {
    throw std::invalid_argument("sphere subdivisions must be in [0, 6]");
  }
  TriangleMesh mesh = OnePart(part);
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  const double icosahedron[12][3] = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                     {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                     {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  for (const auto& v : icosahedron)
    mesh.vertices.push_back(Eigen::Vector3d(v[0], v[1], v[2]).normalized());
  std::vector<Eigen::Vector3i> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoints;  // shared so that neighbours reuse vertices
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      const int index = static_cast<int>(mesh.vertices.size()) - 1;
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.emplace_back(f[0], ab, ca);
      finer.emplace_back(f[1], bc, ab);
      finer.emplace_back(f[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    faces.swap(finer);
  }
  for (auto& v : mesh.vertices) v *= radius;
  for (const auto& f : faces) AddTriangle(mesh, f[0], f[1], f[2]);
  return mesh;
}

}  // namespace aar_geometry
