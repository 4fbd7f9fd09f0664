#include "aar_geometry/adjacency.h"

#include <algorithm>
#include <unordered_map>

namespace aar_geometry {
namespace {

struct EdgeUse {
  int triangle;
  int slot;      // k: the edge runs from vertex k to vertex (k + 1) % 3 of the triangle
  bool forward;  // runs v0 -> v1
};

}  // namespace

TriangleAdjacency BuildAdjacency(const TriangleMesh& mesh) {
  mesh.Validate();
  const size_t n = mesh.triangles.size();
  TriangleAdjacency adjacency;
  adjacency.vertices.resize(n);
  adjacency.neighbors.assign(n, {-1, -1, -1});

  const uint64_t num_vertices = mesh.vertices.size();
  std::unordered_map<uint64_t, std::vector<EdgeUse>> uses;
  uses.reserve(3 * n);
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) adjacency.vertices[t][k] = tri[k];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      adjacency.degenerate_triangles.push_back(static_cast<int>(t));
      continue;
    }
    const Eigen::Vector3d& p0 = mesh.vertices[tri[0]];
    const Eigen::Vector3d& p1 = mesh.vertices[tri[1]];
    const Eigen::Vector3d& p2 = mesh.vertices[tri[2]];
    const double longest_sq =
        std::max({(p1 - p0).squaredNorm(), (p2 - p1).squaredNorm(), (p0 - p2).squaredNorm()});
    if (!((p1 - p0).cross(p2 - p0).norm() > kZeroAreaRatio * longest_sq)) {
      adjacency.zero_area_triangles.push_back(static_cast<int>(t));
    }
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k];
      const int b = mesh.triangles[t][(k + 1) % 3];
      const uint64_t key = static_cast<uint64_t>(std::min(a, b)) * num_vertices + std::max(a, b);
      uses[key].push_back({static_cast<int>(t), k, a < b});
    }
  }

  for (const auto& [key, edge_uses] : uses) {
    const Edge edge{static_cast<int>(key / num_vertices), static_cast<int>(key % num_vertices)};
    if (edge_uses.size() == 1) {
      adjacency.open_edges.push_back(edge);
    } else if (edge_uses.size() > 2) {
      adjacency.nonmanifold_edges.push_back(edge);
    } else {
      const EdgeUse& a = edge_uses[0];
      const EdgeUse& b = edge_uses[1];
      adjacency.neighbors[a.triangle][a.slot] = b.triangle;
      adjacency.neighbors[b.triangle][b.slot] = a.triangle;
      if (a.forward == b.forward) adjacency.inconsistent_edges.push_back(edge);
    }
  }
  // Deterministic order for reports and tests (the hash map's order is not).
  auto by_vertices = [](const Edge& x, const Edge& y) {
    return x.v0 != y.v0 ? x.v0 < y.v0 : x.v1 < y.v1;
  };
  std::sort(adjacency.open_edges.begin(), adjacency.open_edges.end(), by_vertices);
  std::sort(adjacency.nonmanifold_edges.begin(), adjacency.nonmanifold_edges.end(), by_vertices);
  std::sort(adjacency.inconsistent_edges.begin(), adjacency.inconsistent_edges.end(), by_vertices);
  return adjacency;
}

std::string TriangleAdjacency::NotClosedReason() const {
  std::string reason;
  auto add = [&](size_t count, const std::string& one, const std::string& many) {
    if (count == 0) return;
    reason +=
        (reason.empty() ? "" : ", ") + std::to_string(count) + " " + (count == 1 ? one : many);
  };
  add(open_edges.size(), "open edge", "open edges");
  add(nonmanifold_edges.size(), "non-manifold edge", "non-manifold edges");
  add(inconsistent_edges.size(), "inconsistently wound edge", "inconsistently wound edges");
  add(degenerate_triangles.size(), "triangle with a repeated vertex",
      "triangles with a repeated vertex");
  add(zero_area_triangles.size(), "zero-area triangle", "zero-area triangles");
  const size_t faces = vertices.size() - degenerate_triangles.size();
  if (faces < 4) {
    reason += (reason.empty() ? "" : ", ") + std::to_string(faces) +
              " triangles, fewer than a tetrahedron's 4";
  }
  return reason;
}

bool IsConvex(const TriangleMesh& mesh, double tolerance) {
  mesh.Validate();
  // No volume, no convex body (a two-sided sheet passes the plane test otherwise).
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]])) / 6.0;
  }
  if (!(volume > 0.0)) return false;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = mesh.TriangleNormal(static_cast<int>(t));
    if (n.isZero()) continue;
    const double offset = n.dot(mesh.vertices[mesh.triangles[t][0]]);
    for (const auto& v : mesh.vertices) {
      if (n.dot(v) - offset > tolerance) return false;
    }
  }
  return true;
}

}  // namespace aar_geometry
