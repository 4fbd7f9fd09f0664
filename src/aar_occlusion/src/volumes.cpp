#include "aar_occlusion/volumes.h"

#include <algorithm>
#include <stdexcept>

namespace aar_occlusion {

ConvexVolume ConvexVolume::Transformed(const Eigen::Isometry3d& T) const {
  ConvexVolume out;
  for (const auto& p : planes) {
    Plane q;
    q.normal = T.linear() * p.normal;
    q.offset = p.offset + q.normal.dot(T.translation());
    out.planes.push_back(q);
  }
  return out;
}

PartView ViewPart(const aar_geometry::TriangleMesh& mesh,
                  const aar_geometry::TriangleAdjacency& adjacency, const Eigen::Vector3d& eye,
                  const std::string& part, bool validate) {
  if (validate && !adjacency.closed()) {
    throw std::invalid_argument("part '" + part + "' is not closed (" +
                                adjacency.NotClosedReason() +
                                "): shadow volumes need closed parts");
  }
  if (validate && !aar_geometry::IsConvex(mesh)) {
    throw std::invalid_argument("part '" + part +
                                "' is not convex: point inclusion by planes needs convex parts");
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices) centroid += v;
  centroid /= static_cast<double>(mesh.vertices.size());

  PartView view;
  const size_t n = mesh.triangles.size();
  view.facing.resize(n);
  std::vector<Plane> facing_planes;
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3d normal = mesh.TriangleNormal(static_cast<int>(t));
    const Eigen::Vector3d& v0 = mesh.vertices[mesh.triangles[t][0]];
    // Facing: the eye on the outer side of the triangle's plane (thesis: the sign of the dot
    // product of the triangle normal with the direction to the camera).
    view.facing[t] = normal.dot(eye - v0) > 0.0;
    if (view.facing[t]) facing_planes.push_back({normal, normal.dot(v0)});
  }
  // Inside a convex part the eye is on the inner side of every plane: nothing faces it.
  if (facing_planes.empty()) throw std::invalid_argument("the eye is inside part '" + part + "'");

  for (size_t t = 0; t < n; ++t) {
    if (!view.facing[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const int neighbour = adjacency.neighbors[t][k];
      if (neighbour >= 0 && view.facing[neighbour]) continue;
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      view.silhouette.push_back({a, b});
      // Side plane through the eye and the edge, normal pointing away from the part.
      Plane side;
      side.normal = (mesh.vertices[a] - eye).cross(mesh.vertices[b] - eye).normalized();
      side.offset = side.normal.dot(eye);
      if (side.SignedDistance(centroid) > 0.0)
        side.normal = -side.normal, side.offset = -side.offset;
      view.cone.planes.push_back(side);
    }
  }
  // Long silhouette edges first: their planes reject most outside points at the first test.
  std::vector<size_t> order(view.silhouette.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto length = [&](size_t i) {
    return (mesh.vertices[view.silhouette[i].from] - mesh.vertices[view.silhouette[i].to]).norm();
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return length(a) > length(b); });
  std::vector<Plane> sorted;
  std::vector<SilhouetteEdge> edges;
  for (const size_t i : order) {
    sorted.push_back(view.cone.planes[i]);
    edges.push_back(view.silhouette[i]);
  }
  view.cone.planes = std::move(sorted);
  view.silhouette = std::move(edges);
  view.shadow = view.cone;
  view.light = view.cone;
  for (const auto& p : facing_planes) {
    view.shadow.planes.push_back(p);                      // behind the front surface
    view.light.planes.push_back({-p.normal, -p.offset});  // in front of it
  }
  return view;
}

aar_geometry::TriangleMesh ShadowVolumeMesh(const aar_geometry::TriangleMesh& mesh,
                                            const PartView& view, const Eigen::Vector3d& eye,
                                            double length) {
  aar_geometry::TriangleMesh out;
  out.AddPart("shadow");
  out.vertices = mesh.vertices;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (view.facing[t]) out.triangles.push_back(mesh.triangles[t]);
  }
  for (const auto& edge : view.silhouette) {
    const int a = edge.from, b = edge.to;
    const int far = static_cast<int>(out.vertices.size());
    out.vertices.push_back(mesh.vertices[a] + length * (mesh.vertices[a] - eye).normalized());
    out.vertices.push_back(mesh.vertices[b] + length * (mesh.vertices[b] - eye).normalized());
    // Wound so that the side faces point out of the volume.
    out.triangles.emplace_back(b, a, far);
    out.triangles.emplace_back(b, far, far + 1);
  }
  out.triangle_parts.assign(out.triangles.size(), 0);
  return out;
}

std::vector<Visibility> Classify(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<ConvexVolume>& left,
                                 const std::vector<ConvexVolume>& right) {
  auto hidden = [](const Eigen::Vector3d& p, const std::vector<ConvexVolume>& shadows) {
    for (const auto& s : shadows) {
      if (s.Contains(p)) return true;
    }
    return false;
  };
  std::vector<Visibility> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      out[i] = Visibility::kNeither;  // nowhere: seen by no camera
      continue;
    }
    const bool l = !hidden(points[i], left), r = !hidden(points[i], right);
    out[i] = l && r ? Visibility::kBoth
             : l    ? Visibility::kLeftOnly
             : r    ? Visibility::kRightOnly
                    : Visibility::kNeither;
  }
  return out;
}

}  // namespace aar_occlusion
