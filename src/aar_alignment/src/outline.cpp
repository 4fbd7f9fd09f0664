#include "aar_alignment/outline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/weld.h>
#include <opencv2/imgproc.hpp>

namespace aar_alignment {
namespace {

constexpr double kMinDepth = 0.1;  // [m] vertices nearer the camera's plane: no outline
constexpr int kOversample = 3;     // edge samples per wanted outline point (most are inside)

using Mask = SilhouetteMask;

// Sets the mask pixels whose centres (integer coordinates) lie in the triangle a, b, c [mask px]:
// exact coverage, unlike a rasteriser that also draws the edges.
void FillTriangle(cv::Mat& mask, Eigen::Vector2d a, Eigen::Vector2d b, Eigen::Vector2d c) {
  const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  if (area == 0.0) return;
  if (area < 0.0) std::swap(b, c);
  const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({a.x(), b.x(), c.x()}))));
  const int x1 =
      std::min(mask.cols - 1, static_cast<int>(std::floor(std::max({a.x(), b.x(), c.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({a.y(), b.y(), c.y()}))));
  const int y1 =
      std::min(mask.rows - 1, static_cast<int>(std::floor(std::max({a.y(), b.y(), c.y()}))));
  // Edge functions e(p) = (q - p0) x (p1 - p0) >= 0 inside, stepped along the row.
  const Eigen::Vector2d v[3] = {a, b, c};
  for (int y = y0; y <= y1; ++y) {
    uint8_t* row = mask.ptr<uint8_t>(y);
    for (int x = x0; x <= x1; ++x) {
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const Eigen::Vector2d& p0 = v[k];
        const Eigen::Vector2d& p1 = v[(k + 1) % 3];
        inside = (p1.x() - p0.x()) * (y - p0.y()) - (p1.y() - p0.y()) * (x - p0.x()) >= 0.0;
      }
      if (inside) row[x] = 1;
    }
  }
}

// The triangles facing the camera (their union is the receiver's image) as a mask about
// `mask_size` px across, of the part within 64 px of the image.
Mask DrawMask(const aar_geometry::TriangleMesh& mesh, const std::vector<char>& front,
              const std::vector<Eigen::Vector2d>& pixels, const PinholeCamera& camera,
              int mask_size, double max_scale) {
  Eigen::AlignedBox2d box;
  for (const auto& u : pixels) box.extend(u);
  const Eigen::Vector2d margin(64.0, 64.0);
  const Eigen::AlignedBox2d view(-margin, Eigen::Vector2d(camera.width, camera.height) + margin);
  box = box.intersection(view);
  Mask mask;
  if (box.isEmpty()) return mask;
  const Eigen::Vector2d size = box.sizes();
  mask.scale = std::min(max_scale, mask_size / std::max(1.0, size.maxCoeff()));
  mask.origin = box.min() - Eigen::Vector2d(2.0, 2.0) / mask.scale;
  mask.image = cv::Mat::zeros(static_cast<int>(std::ceil(size.y() * mask.scale)) + 5,
                              static_cast<int>(std::ceil(size.x() * mask.scale)) + 5, CV_8U);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!front[t]) continue;
    const Eigen::Vector3i& v = mesh.triangles[t];
    FillTriangle(mask.image, (pixels[v[0]] - mask.origin) * mask.scale,
                 (pixels[v[1]] - mask.origin) * mask.scale,
                 (pixels[v[2]] - mask.origin) * mask.scale);
  }
  return mask;
}

// The mask along the line through an outline point (ContourPoint::profile).
std::vector<uint8_t> Profile(const Mask& mask, const Eigen::Vector2d& pixel,
                             const Eigen::Vector2d& normal, int half_length) {
  const double exact = 2.0 / mask.scale;  // [px] the mask's own edge is this uncertain
  std::vector<uint8_t> profile(2 * static_cast<size_t>(half_length));
  for (int i = 0; i < 2 * half_length; ++i) {
    const double x = i - half_length + 0.5;
    profile[i] = std::abs(x) < exact ? x < 0.0 : mask.At(pixel + x * normal);
  }
  return profile;
}

}  // namespace

bool SilhouetteMask::At(const Eigen::Vector2d& pixel) const {
  // OpenCV's polygons cover the pixels whose centres (integers) lie inside.
  const Eigen::Vector2d m = (pixel - origin) * scale;
  const int x = static_cast<int>(std::floor(m.x() + 0.5)),
            y = static_cast<int>(std::floor(m.y() + 0.5));
  return x >= 0 && y >= 0 && x < image.cols && y < image.rows && image.at<uint8_t>(y, x) != 0;
}

bool OutlineModel::Project(const PinholeCamera& camera, const Eigen::Isometry3d& T_tanker_receiver,
                           std::vector<Eigen::Vector3d>& y, std::vector<Eigen::Vector2d>& u) const {
  const Eigen::Isometry3d T_optical_body = camera.T_tanker_optical.inverse() * T_tanker_receiver;
  y.resize(mesh_.vertices.size());
  u.resize(mesh_.vertices.size());
  for (size_t i = 0; i < y.size(); ++i) {
    y[i] = T_optical_body * mesh_.vertices[i];
    if (!(y[i].z() > kMinDepth)) return false;
    u[i] = camera.Project(y[i]);
  }
  return true;
}

std::vector<char> OutlineModel::Facing(const std::vector<Eigen::Vector3d>& y) const {
  std::vector<char> front(mesh_.triangles.size());
  for (size_t t = 0; t < front.size(); ++t) {
    const Eigen::Vector3i& v = mesh_.triangles[t];
    front[t] = (y[v[1]] - y[v[0]]).cross(y[v[2]] - y[v[0]]).dot(y[v[0]]) < 0.0;
  }
  return front;
}

SilhouetteMask OutlineModel::Silhouette(const PinholeCamera& camera,
                                        const Eigen::Isometry3d& T_tanker_receiver, int size,
                                        double max_scale) const {
  std::vector<Eigen::Vector3d> y;
  std::vector<Eigen::Vector2d> u;
  if (!Project(camera, T_tanker_receiver, y, u)) return {};
  return DrawMask(mesh_, Facing(y), u, camera, size, max_scale);
}

OutlineModel::OutlineModel(const aar_geometry::TriangleMesh& receiver) {
  receiver.Validate();
  if (receiver.empty()) throw std::invalid_argument("OutlineModel: the receiver mesh is empty");
  mesh_ = aar_geometry::WeldVertices(receiver).mesh;
  for (const Eigen::Vector3d& v : mesh_.vertices) radius_ = std::max(radius_, v.norm());
  const aar_geometry::TriangleAdjacency adjacency = aar_geometry::BuildAdjacency(mesh_);
  for (size_t t = 0; t < adjacency.vertices.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int n = adjacency.neighbors[t][k];
      if (n >= 0 && n < static_cast<int>(t)) continue;  // taken from the other side
      edges_.push_back(
          {adjacency.vertices[t][k], adjacency.vertices[t][(k + 1) % 3], static_cast<int>(t), n});
    }
  }
}

std::vector<ContourPoint> OutlineModel::Contour(const PinholeCamera& camera,
                                                const Eigen::Isometry3d& T_tanker_receiver,
                                                int count, int profile_half_length, int mask_size,
                                                double mask_max_scale) const {
  const Eigen::Isometry3d T_optical_body = camera.T_tanker_optical.inverse() * T_tanker_receiver;
  std::vector<Eigen::Vector3d> y;
  std::vector<Eigen::Vector2d> u;
  if (!Project(camera, T_tanker_receiver, y, u)) return {};
  const std::vector<char> front = Facing(y);
  const Mask mask = DrawMask(mesh_, front, u, camera, mask_size, mask_max_scale);
  if (mask.image.empty() || count <= 0) return {};

  std::vector<const MeshEdge*> silhouette;
  double length = 0.0;  // [px] of the silhouette edges in the image
  for (const MeshEdge& e : edges_) {
    if (e.t1 >= 0 && front[e.t0] == front[e.t1]) continue;
    silhouette.push_back(&e);
    length += (u[e.v1] - u[e.v0]).norm();
  }
  const double spacing = length / (kOversample * count);  // [px]
  const double probe = 1.5 / mask.scale;                  // [px] 1.5 mask pixels
  std::vector<ContourPoint> outer;
  double next = 0.5 * spacing;  // [px] along the silhouette, carried from edge to edge
  for (const MeshEdge* e : silhouette) {
    const Eigen::Vector2d d = u[e->v1] - u[e->v0];
    const double len = d.norm();
    if (len <= 0.0) continue;
    const Eigen::Vector2d n(-d.y() / len, d.x() / len);
    for (; next < len; next += spacing) {
      const double f = next / len;
      ContourPoint p;
      p.body = (1.0 - f) * mesh_.vertices[e->v0] + f * mesh_.vertices[e->v1];
      p.pixel = camera.Project(T_optical_body * p.body);
      const bool plus = mask.At(p.pixel + probe * n), minus = mask.At(p.pixel - probe * n);
      if (plus == minus) continue;  // inside the receiver's image, or a sliver
      p.normal = plus ? Eigen::Vector2d(-n) : n;
      outer.push_back(p);
    }
    next -= len;
  }
  std::vector<ContourPoint> picked;
  const double stride = std::max(1.0, static_cast<double>(outer.size()) / count);
  for (double i = 0.0; i < outer.size(); i += stride) {
    picked.push_back(outer[static_cast<size_t>(i)]);
    picked.back().profile =
        Profile(mask, picked.back().pixel, picked.back().normal, profile_half_length);
  }
  return picked;
}

}  // namespace aar_alignment
