#include "aar_geometry/receiver_check.h"

#include <cmath>
#include <numeric>
#include <sstream>

#include "aar_geometry/adjacency.h"
#include "aar_geometry/load_error.h"
#include "aar_geometry/weld.h"

namespace aar_geometry {
namespace {

std::string Metres(double v) {
  std::ostringstream s;
  s.precision(v >= 100.0 ? 0 : 2);
  s << std::fixed << v << " m";
  return s.str();
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Solid angle of triangle (a, b, c) seen from the origin, over 4 pi (Van Oosterom and
// Strackee): the triangle's share of the generalised winding number.
double WindingShare(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return std::atan2(numerator, denominator) / (2.0 * M_PI);
}

}  // namespace

ReceiverCheckResult CheckReceiverMesh(const TriangleMesh& mesh, const std::string& path,
                                      const ReceiverCheckOptions& o) {
  ReceiverCheckResult result;
  if (mesh.triangles.empty()) throw LoadError(path, "the receiver model has no faces");
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) throw LoadError(path, "the receiver model has a non-finite vertex");
  }
  result.size = mesh.Bounds().sizes();
  const double extent = result.size.maxCoeff();
  std::ostringstream sides;
  sides << "(x " << Metres(result.size.x()) << ", y " << Metres(result.size.y()) << ", z "
        << Metres(result.size.z()) << ")";
  if (!(extent <= o.max_extent)) {
    throw LoadError(path, "the receiver model is " + Metres(extent) + " across " + sides.str() +
                              ", larger than any aircraft (at most " + Metres(o.max_extent) +
                              "): wrong units? A mesh in millimetres needs scale: 0.001 in its "
                              "receiver description");
  }
  if (!(extent >= o.min_extent)) {
    throw LoadError(path, "the receiver model is " + Metres(extent) + " across " + sides.str() +
                              ", smaller than any aircraft (at least " + Metres(o.min_extent) +
                              "): wrong units or scale in its receiver description?");
  }

  const TriangleMesh welded = WeldVertices(mesh, o.weld_epsilon).mesh;
  if (welded.triangles.empty()) throw LoadError(path, "the receiver model has no faces of area");
  const TriangleAdjacency adjacency = BuildAdjacency(welded);
  result.open_edges = adjacency.open_edges.size();
  if (adjacency.open_edges.empty()) return result;

  // Connected components by shared vertices: an open edge is covered when it lies inside
  // another component (a wing root inside the fuselage).
  std::vector<int> parent(welded.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& t : welded.triangles) {
    parent[Find(parent, t[1])] = Find(parent, t[0]);
    parent[Find(parent, t[2])] = Find(parent, t[0]);
  }
  std::vector<int> triangle_component;
  for (const auto& t : welded.triangles) triangle_component.push_back(Find(parent, t[0]));
  Eigen::Vector3d example = Eigen::Vector3d::Zero();
  for (const Edge& e : adjacency.open_edges) {
    const Eigen::Vector3d mid = 0.5 * (welded.vertices[e.v0] + welded.vertices[e.v1]);
    const int component = Find(parent, e.v0);
    double winding = 0.0;
    for (size_t i = 0; i < welded.triangles.size(); ++i) {
      if (triangle_component[i] == component) continue;
      const auto& t = welded.triangles[i];
      winding += WindingShare(welded.vertices[t[0]] - mid, welded.vertices[t[1]] - mid,
                              welded.vertices[t[2]] - mid);
    }
    if (std::abs(winding) < 0.5) {
      if (result.exposed_open_edges == 0) example = mid;
      ++result.exposed_open_edges;
      result.exposed_open_length += (welded.vertices[e.v1] - welded.vertices[e.v0]).norm();
    }
  }
  if (result.exposed_open_length > o.max_exposed_open_length) {
    std::ostringstream s;
    s << "the receiver model is open: " << result.exposed_open_edges << " of " << result.open_edges
      << " edges used by one triangle (" << Metres(result.exposed_open_length)
      << " in all) lie outside the rest of the model, e.g. at (" << example.x() << ", "
      << example.y() << ", " << example.z()
      << ") m; sampling and self-occlusion need a closed surface";
    throw LoadError(path, s.str());
  }
  return result;
}

}  // namespace aar_geometry
