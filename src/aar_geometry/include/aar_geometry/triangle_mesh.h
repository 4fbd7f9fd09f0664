#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace aar_geometry {

// An indexed triangle mesh whose triangles carry a part label (index into part_names), so that
// subsets such as "wings and nose" or one convex collision part can be selected.
// Triangles are counter-clockwise seen from outside: normals point out of closed meshes.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;   // [m]
  std::vector<Eigen::Vector3i> triangles;  // vertex indices
  std::vector<int> triangle_parts;         // one per triangle, index into part_names
  std::vector<std::string> part_names;

  bool empty() const { return triangles.empty(); }

  // Index of a part, added if not present.
  int AddPart(const std::string& name);
  // Index of a part, or -1.
  int FindPart(const std::string& name) const;

  // Appends other's triangles mapped through T_this_other (a mirror keeps normals pointing out);
  // parts with the same name are merged. Throws std::invalid_argument if `other` is malformed.
  void Append(const TriangleMesh& other,
              const Eigen::Isometry3d& T_this_other = Eigen::Isometry3d::Identity());

  // Unit normal from the winding; zero for a degenerate triangle. `triangle` must be valid.
  Eigen::Vector3d TriangleNormal(int triangle) const;
  double TriangleArea(int triangle) const;  // [m^2]
  double SurfaceArea() const;               // [m^2]
  Eigen::AlignedBox3d Bounds() const;

  // Throws std::invalid_argument when indices or labels are out of range.
  void Validate() const;
};

// Maps the vertices through T_new_old; a mirror (determinant -1) reverses the winding so that
// normals keep pointing out.
TriangleMesh Transformed(const TriangleMesh& mesh, const Eigen::Isometry3d& T_new_old);

// Scales vertex coordinates per axis; an odd number of negative factors reverses the winding so
// that normals keep pointing out. Throws std::invalid_argument for a zero or non-finite factor.
TriangleMesh Scaled(const TriangleMesh& mesh, const Eigen::Vector3d& scale);

// The triangles whose part is in `parts` (unused vertices dropped). Throws std::invalid_argument
// naming any part the mesh does not have, or if the mesh is malformed.
TriangleMesh SelectParts(const TriangleMesh& mesh, const std::vector<std::string>& parts);

}  // namespace aar_geometry
