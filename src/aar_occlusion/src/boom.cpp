#include "aar_occlusion/boom.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Dense>

#include <aar_geometry/receiver_reference.h>

namespace aar_occlusion {

using aar_geometry::TriangleMesh;

TriangleMesh Inflate(const TriangleMesh& mesh, double margin) {
  std::vector<std::vector<Eigen::Vector3d>> normals(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = mesh.TriangleNormal(static_cast<int>(t));
    if (n.isZero()) continue;
    for (int k = 0; k < 3; ++k) {
      auto& list = normals[mesh.triangles[t][k]];
      bool known = false;
      for (const auto& m : list) known = known || m.dot(n) > 1.0 - 1e-6;  // within 1.4 mrad
      if (!known) list.push_back(n);
    }
  }
  TriangleMesh out = mesh;
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto& list = normals[v];
    if (list.empty()) continue;
    Eigen::MatrixXd A(list.size(), 3);
    for (size_t i = 0; i < list.size(); ++i) A.row(i) = list[i].transpose();
    // Minimum-norm least squares: a vertex on a flat face moves along its normal.
    const Eigen::VectorXd b = Eigen::VectorXd::Constant(list.size(), margin);
    out.vertices[v] += A.completeOrthogonalDecomposition().solve(b);
  }
  return out;
}

std::vector<BoomPart> LoadBoomParts(const aar_geometry::RobotModel& model,
                                    const BoomPartsOptions& options) {
  for (const double margin : {options.cull_margin, options.silhouette_margin}) {
    if (!(margin >= 0.0))
      throw std::invalid_argument("boom margins must be >= 0, not " + std::to_string(margin));
  }
  // Culling by volumes tests the outline inside the grown boom's cone.
  if (options.silhouette_margin > options.cull_margin) {
    throw std::invalid_argument(
        "the silhouette margin (" + std::to_string(options.silhouette_margin) +
        " m) must not exceed the cull margin (" + std::to_string(options.cull_margin) + " m)");
  }
  std::vector<BoomPart> parts;
  for (aar_description::BoomCollisionPart& collision :
       aar_description::LoadBoomCollisionParts(model)) {
    BoomPart part;
    static_cast<aar_description::BoomCollisionPart&>(part) = std::move(collision);
    const auto grow = [&](double margin) {
      TriangleMesh grown = Inflate(part.mesh, margin);
      // Least-squares corners on thin facets may dent by a fraction of a millimetre.
      if (!aar_geometry::IsConvex(grown, 1e-4 + 1e-2 * margin)) {
        throw std::invalid_argument("collision part '" + part.name + "' of boom link '" +
                                    part.link + "' is not convex once grown by " +
                                    std::to_string(margin) + " m");
      }
      return grown;
    };
    part.grown = grow(options.cull_margin);
    part.grown_adjacency = aar_geometry::BuildAdjacency(part.grown);
    part.outline = grow(options.silhouette_margin);
    part.outline_adjacency = aar_geometry::BuildAdjacency(part.outline);
    parts.push_back(std::move(part));
  }
  return parts;
}

BoomOcclusion::BoomOcclusion(std::vector<BoomPart> parts, const BoomOcclusionOptions& options)
    : parts_(std::move(parts)), options_(options) {
  if (parts_.empty()) throw std::invalid_argument("BoomOcclusion: no boom parts");
  if (!(options_.cull_depth_coefficient >= 0.0))
    throw std::invalid_argument("BoomOcclusion: cull_depth_coefficient must be >= 0");
}

BoomOcclusion::~BoomOcclusion() = default;

std::vector<std::string> BoomOcclusion::links() const {
  std::vector<std::string> out;
  for (const auto& p : parts_) {
    if (std::find(out.begin(), out.end(), p.link) == out.end()) out.push_back(p.link);
  }
  return out;
}

bool BoomOcclusion::Moved(const std::map<std::string, Eigen::Isometry3d>& T_tanker_links,
                          const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye) const {
  if (!ready_) return true;
  const double tol = options_.rebuild_tolerance;
  if ((left_eye - eyes_[0]).cwiseAbs().maxCoeff() > tol ||
      (right_eye - eyes_[1]).cwiseAbs().maxCoeff() > tol)
    return true;
  for (const auto& [link, T_old] : T_tanker_links_) {
    const Eigen::Isometry3d& T_new = T_tanker_links.at(link);
    // Rotation entries times a 10 m lever: about the motion of the boom's far end.
    if ((T_new.translation() - T_old.translation()).cwiseAbs().maxCoeff() > tol ||
        10.0 * (T_new.linear() - T_old.linear()).cwiseAbs().maxCoeff() > tol)
      return true;
  }
  return false;
}

bool BoomOcclusion::Update(const std::map<std::string, Eigen::Isometry3d>& T_tanker_links,
                           const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye) {
  std::map<std::string, Eigen::Isometry3d> used;
  for (const auto& link : links()) {
    const auto it = T_tanker_links.find(link);
    if (it == T_tanker_links.end())
      throw std::invalid_argument("no pose for boom link '" + link + "'");
    if (!it->second.matrix().allFinite())
      throw std::invalid_argument("the pose of boom link '" + link + "' is not finite");
    used[link] = it->second;
  }
  if (!left_eye.allFinite() || !right_eye.allFinite())
    throw std::invalid_argument("a camera position is not finite");
  if (!Moved(used, left_eye, right_eye)) return false;

  ready_ = false;  // stays false if a part refuses an eye below
  const Eigen::Vector3d eyes[2] = {left_eye, right_eye};
  std::vector<Eigen::Isometry3d> T_parts;
  std::vector<PartView> views[2];
  std::vector<ConvexVolume> shadows[2];
  std::vector<CullVolume> cull;
  TriangleMesh grown, outline;
  for (const auto& part : parts_) {
    const Eigen::Isometry3d T = used.at(part.link) * part.T_link_part;
    const Eigen::Isometry3d T_inv = T.inverse();
    const std::string name = part.name + "' of link '" + part.link;
    T_parts.push_back(T);
    for (int e = 0; e < 2; ++e) {
      // Thesis Eq. 4-5: the eye in the part's frame; the planes go back to the tanker frame.
      views[e].push_back(ViewPart(part.mesh, part.adjacency, T_inv * eyes[e], name, false));
      shadows[e].push_back(views[e].back().shadow.Transformed(T));
    }
    // Culling is from the left eye: stereo points lie on its pixel rays.
    const PartView near =
        ViewPart(part.grown, part.grown_adjacency, T_inv * eyes[0], name + "' (grown)", false);
    CullVolume volume;
    volume.cone = near.cone.Transformed(T);  // light volume, part and shadow: the whole ray
    if (!options_.cull_behind_boom) {
      // Up to the far side: inside the planes of the triangles turned away from the eye (the eye
      // is inside them all, and a ray leaves the part through one of them).
      for (size_t t = 0; t < part.grown.triangles.size(); ++t) {
        if (near.facing[t]) continue;
        const Eigen::Vector3d n = part.grown.TriangleNormal(static_cast<int>(t));
        volume.far_side.planes.push_back(
            {n, n.dot(part.grown.vertices[part.grown.triangles[t][0]])});
      }
      volume.far_side = volume.far_side.Transformed(T);
      volume.outline = ViewPart(part.outline, part.outline_adjacency, T_inv * eyes[0],
                                name + "' (outline)", false)
                           .cone.Transformed(T);
    }
    cull.push_back(std::move(volume));
    grown.Append(part.grown, T);
    outline.Append(part.outline, T);
  }
  grown_boom_ = std::move(grown);
  outline_boom_ = std::move(outline);
  ray_targets_built_ = false;
  T_tanker_links_ = std::move(used);
  eyes_[0] = left_eye;
  eyes_[1] = right_eye;
  T_tanker_parts_ = std::move(T_parts);
  for (int e = 0; e < 2; ++e) {
    views_[e] = std::move(views[e]);
    shadows_[e] = std::move(shadows[e]);
  }
  cull_ = std::move(cull);
  ready_ = true;
  return true;
}

bool BoomOcclusion::CullVolume::Contains(const Eigen::Vector3d& p,
                                         const Eigen::Vector3d& p_toward_eye) const {
  // The outline's cone lies inside the grown part's: outside that, outside both.
  if (!cone.Contains(p)) return false;
  if (far_side.planes.empty()) return true;  // the whole ray
  return far_side.Contains(p_toward_eye) || outline.Contains(p);
}

Eigen::Vector3d BoomOcclusion::TowardEye(const Eigen::Vector3d& p) const {
  const double margin = options_.cull_depth_coefficient * (p - eyes_[0]).squaredNorm();
  return margin > 0.0 ? Eigen::Vector3d(p - margin * (p - eyes_[0]).normalized()) : p;
}

void BoomOcclusion::BuildRayTargets() const {
  if (ray_targets_built_) return;
  grown_.Build(grown_boom_);
  outline_.Build(outline_boom_);
  ray_targets_built_ = true;
}

void BoomOcclusion::RayTarget::Build(const TriangleMesh& mesh) {
  triangles.clear();
  for (const auto& t : mesh.triangles) {
    Eigen::Matrix3d m;
    m.col(0) = mesh.vertices[t[0]];
    m.col(1) = mesh.vertices[t[1]] - mesh.vertices[t[0]];
    m.col(2) = mesh.vertices[t[2]] - mesh.vertices[t[0]];
    triangles.push_back(m);
  }
  bvh = std::make_unique<aar_geometry::VisibilityTester>(mesh);
}

bool BoomOcclusion::RayTarget::HitsBrute(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
  // Moller-Trumbore, any hit ahead of the origin.
  for (const auto& m : triangles) {
    const Eigen::Vector3d e1 = m.col(1), e2 = m.col(2);
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-12) continue;
    const double inv = 1.0 / det;
    const Eigen::Vector3d s = o - m.col(0);
    const double u = s.dot(p) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    if (e2.dot(q) * inv > 0.0) return true;
  }
  return false;
}

std::vector<bool> BoomOcclusion::Cull(const std::vector<Eigen::Vector3d>& points,
                                      CullMethod method) const {
  if (!ready_) throw std::logic_error("BoomOcclusion::Cull before a successful Update");
  std::vector<bool> boom(points.size(), false);
  const bool behind = options_.cull_behind_boom;
  std::vector<Eigen::Vector3d> directions;  // from the eye through each point: the rays only
  if (method == CullMethod::kRaysBrute || method == CullMethod::kRaysBvh) {
    BuildRayTargets();
    directions.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) directions[i] = (points[i] - eyes_[0]).normalized();
  }
  // Rays: from the eye through the point against the grown boom (thesis), or else from the point
  // (moved toward the eye by its depth margin) on away from the eye against the grown boom (it
  // hits exactly when the point is in front of the far side) and from the eye through the point
  // against the outline.
  std::vector<Eigen::Vector3d> starts;  // the points moved toward the eye by their depth margin
  if (!behind && (method == CullMethod::kRaysBrute || method == CullMethod::kRaysBvh)) {
    starts = points;
    for (size_t i = 0; i < points.size(); ++i) {
      if (directions[i].allFinite()) starts[i] = TowardEye(points[i]);
    }
  }
  switch (method) {
    case CullMethod::kNone:
      break;
    case CullMethod::kRaysBrute:
      for (size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d& d = directions[i];
        if (!d.allFinite()) continue;
        boom[i] = behind ? grown_.HitsBrute(eyes_[0], d)
                         : grown_.HitsBrute(starts[i], d) || outline_.HitsBrute(eyes_[0], d);
      }
      break;
    case CullMethod::kRaysBvh: {
      const std::vector<Eigen::Vector3d> eye(points.size(), eyes_[0]);
      boom = grown_.bvh->RaysHit(behind ? eye : starts, directions);
      if (!behind) {
        const std::vector<bool> through = outline_.bvh->RaysHit(eye, directions);
        for (size_t i = 0; i < points.size(); ++i) boom[i] = boom[i] || through[i];
      }
      break;
    }
    case CullMethod::kVolumes:
      for (size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) continue;  // as the rays: no direction, not boom
        const Eigen::Vector3d toward_eye = TowardEye(points[i]);
        for (const auto& v : cull_) {
          if (v.Contains(points[i], toward_eye)) {
            boom[i] = true;
            break;
          }
        }
      }
      break;
  }
  return boom;
}

bool BoomOcclusion::Hidden(const Eigen::Vector3d& point, int eye) const {
  for (const auto& s : shadows_[eye]) {
    if (s.Contains(point)) return true;
  }
  return false;
}

std::vector<Visibility> BoomOcclusion::Classify(const std::vector<Eigen::Vector3d>& points) const {
  if (!ready_) throw std::logic_error("BoomOcclusion::Classify before a successful Update");
  return aar_occlusion::Classify(points, shadows_[0], shadows_[1]);
}

}  // namespace aar_occlusion
