#include "aar_geometry/triangle_mesh.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace aar_geometry {

int TriangleMesh::AddPart(const std::string& name) {
  const int found = FindPart(name);
  if (found >= 0) return found;
  part_names.push_back(name);
  return static_cast<int>(part_names.size()) - 1;
}

int TriangleMesh::FindPart(const std::string& name) const {
  const auto it = std::find(part_names.begin(), part_names.end(), name);
  return it == part_names.end() ? -1 : static_cast<int>(it - part_names.begin());
}

void TriangleMesh::Append(const TriangleMesh& other, const Eigen::Isometry3d& T_this_other) {
  other.Validate();
  const bool mirrored = T_this_other.linear().determinant() < 0.0;
  const int offset = static_cast<int>(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices) vertices.push_back(T_this_other * v);

  std::vector<int> part_map(other.part_names.size());
  for (size_t p = 0; p < other.part_names.size(); ++p) part_map[p] = AddPart(other.part_names[p]);

  triangles.reserve(triangles.size() + other.triangles.size());
  triangle_parts.reserve(triangle_parts.size() + other.triangles.size());
  for (size_t t = 0; t < other.triangles.size(); ++t) {
    Eigen::Vector3i tri = other.triangles[t].array() + offset;
    if (mirrored) std::swap(tri[1], tri[2]);  // keep normals pointing out
    triangles.push_back(tri);
    triangle_parts.push_back(part_map.at(other.triangle_parts[t]));
  }
}

Eigen::Vector3d TriangleMesh::TriangleNormal(int triangle) const {
  const Eigen::Vector3i& t = triangles[triangle];
  const Eigen::Vector3d n =
      (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

double TriangleMesh::TriangleArea(int triangle) const {
  const Eigen::Vector3i& t = triangles[triangle];
  return 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
}

double TriangleMesh::SurfaceArea() const {
  double area = 0.0;
  for (size_t t = 0; t < triangles.size(); ++t) area += TriangleArea(static_cast<int>(t));
  return area;
}

Eigen::AlignedBox3d TriangleMesh::Bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& v : vertices) box.extend(v);
  return box;
}

void TriangleMesh::Validate() const {
  if (triangle_parts.size() != triangles.size()) {
    throw std::invalid_argument("mesh has " + std::to_string(triangles.size()) + " triangles but " +
                                std::to_string(triangle_parts.size()) + " part labels");
  }
  const int n = static_cast<int>(vertices.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] < 0 || triangles[t][k] >= n) {
        throw std::invalid_argument("triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(triangles[t][k]) + " of " + std::to_string(n));
      }
    }
    if (triangle_parts[t] < 0 || triangle_parts[t] >= static_cast<int>(part_names.size())) {
      throw std::invalid_argument("triangle " + std::to_string(t) + " has part label " +
                                  std::to_string(triangle_parts[t]) + " of " +
                                  std::to_string(part_names.size()));
    }
  }
  for (size_t v = 0; v < vertices.size(); ++v) {
    if (!vertices[v].allFinite()) {
      throw std::invalid_argument("vertex " + std::to_string(v) + " is not finite");
    }
  }
}

TriangleMesh Transformed(const TriangleMesh& mesh, const Eigen::Isometry3d& T_new_old) {
  TriangleMesh out = mesh;
  for (auto& v : out.vertices) v = T_new_old * v;
  if (T_new_old.linear().determinant() < 0.0) {
    for (auto& t : out.triangles) std::swap(t[1], t[2]);  // a mirror: keep normals pointing out
  }
  return out;
}

TriangleMesh Scaled(const TriangleMesh& mesh, const Eigen::Vector3d& scale) {
  if (!scale.allFinite() || (scale.array() == 0.0).any()) {
    throw std::invalid_argument("scale factors must be finite and non-zero");
  }
  TriangleMesh out = mesh;
  for (auto& v : out.vertices) v = v.cwiseProduct(scale);
  if (scale.prod() < 0.0) {
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  }
  return out;
}

TriangleMesh SelectParts(const TriangleMesh& mesh, const std::vector<std::string>& parts) {
  mesh.Validate();
  std::vector<bool> keep_part(mesh.part_names.size(), false);
  for (const auto& name : parts) {
    const int p = mesh.FindPart(name);
    if (p < 0) throw std::invalid_argument("mesh has no part named '" + name + "'");
    keep_part[p] = true;
  }
  TriangleMesh out;
  std::vector<int> part_map(mesh.part_names.size(), -1);
  std::unordered_map<int, int> vertex_map;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int part = mesh.triangle_parts[t];
    if (!keep_part[part]) continue;
    if (part_map[part] < 0) part_map[part] = out.AddPart(mesh.part_names[part]);
    Eigen::Vector3i tri;
    for (int k = 0; k < 3; ++k) {
      const int old_index = mesh.triangles[t][k];
      auto [it, inserted] = vertex_map.emplace(old_index, static_cast<int>(out.vertices.size()));
      if (inserted) out.vertices.push_back(mesh.vertices[old_index]);
      tri[k] = it->second;
    }
    out.triangles.push_back(tri);
    out.triangle_parts.push_back(part_map[part]);
  }
  return out;
}

}  // namespace aar_geometry
