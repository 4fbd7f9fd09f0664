#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <aar_description/boom_parts.h>
#include <aar_geometry/adjacency.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/triangle_mesh.h>

#include "aar_occlusion/volumes.h"

namespace aar_geometry {
class VisibilityTester;
}

namespace aar_occlusion {

// One of the boom's collision parts (aar_description) as culling needs it: grown by both margins.
struct BoomPart : aar_description::BoomCollisionPart {
  aar_geometry::TriangleMesh grown;  // every face pushed out by the cull margin
  aar_geometry::TriangleAdjacency grown_adjacency;
  aar_geometry::TriangleMesh outline;  // pushed out by the silhouette margin
  aar_geometry::TriangleAdjacency outline_adjacency;
};

struct BoomPartsOptions {
  double cull_margin = 0.10;  // [m] a point this close to the boom is boom (thesis: 10 cm)
  // [m] a point on a camera ray through the boom's outline grown by this is boom at any depth:
  // stereo depth on the boom is unreliable (its near end is closer than the disparity search
  // reaches), and the cameras cannot see anything behind the boom.
  double silhouette_margin = 0.02;
};

// Every collision element of the model (aar_description::LoadBoomCollisionParts, which throws
// std::invalid_argument naming a bad link or part) as a BoomPart, grown by both margins for
// culling; also throws for a bad margin or a part that is not convex once grown.
std::vector<BoomPart> LoadBoomParts(const aar_geometry::RobotModel& model,
                                    const BoomPartsOptions& options = {});

// A closed convex mesh with every face plane moved out by `margin` [m] (the thesis's boom
// "extruded equally in all directions"): each vertex moves to the least-squares meeting point of
// its faces' offset planes, exact where at most three distinct planes meet (boxes, cylinders).
// Where two faces meet at a knife edge of angle 2a, that point lies margin / sin(a) out: parts
// need blunt edges (the shipped boom's test bounds every vertex's move by 2 x margin).
aar_geometry::TriangleMesh Inflate(const aar_geometry::TriangleMesh& convex, double margin);

// How sensed points on the boom are found, always from the left camera (stereo points lie on
// its pixel rays).
enum class CullMethod {
  kNone,
  kRaysBrute,  // thesis 3.7: rays against every triangle of the grown boom
  kRaysBvh,    // the same rays through an Embree BVH
  kVolumes,    // the same sets by point inclusion in planes: the fast default
};
CullMethod ParseCullMethod(const std::string& name);  // none|rays_brute|rays_bvh|volumes
std::string ToString(CullMethod method);

struct BoomOcclusionOptions {
  double rebuild_tolerance = 1e-6;  // [m] link or eye motion that rebuilds the volumes

  // Off (default), a point is boom when it lies on a camera ray through the boom grown by the
  // cull margin and not beyond that grown boom's far side, or anywhere on a ray through the
  // outline grown by the silhouette margin: receiver seen just past the boom's edge stays. On,
  // anything on a ray through the boom grown by the cull margin is boom, in front or behind
  // (the thesis's ray test), which also removes the receiver seen within the margin's shadow.
  bool cull_behind_boom = false;
  // [1/m] Off (0, thesis), the far side is where the grown boom ends. Above 0 (ours, issue 29),
  // a point counts as in front of the far side when it lies up to cull_depth_coefficient * Z^2
  // beyond it along its ray (Z its range from the left eye): stereo scatters a point along its
  // ray by sigma_Z = Z^2 sigma_d / (f b), 0.2 m at 30 m for 0.25 px on the shipped rig, more
  // than the cull margin, so the boom's own points land behind its far side and stay.
  // k sigma_d / (f b) covers k sigmas.
  double cull_depth_coefficient = 0.0;
};

// The boom's shadow volumes for two eyes and its cull volumes for the left eye, all in the tanker
// frame, rebuilt whenever a link or an eye moves (thesis 3.8, Eq. 4-6). Not thread-safe: one
// caller at a time (the ray methods build their BVHs on first use).
class BoomOcclusion {
 public:
  explicit BoomOcclusion(std::vector<BoomPart> parts, const BoomOcclusionOptions& options = {});
  ~BoomOcclusion();

  // The links the parts hang on: the poses Update needs.
  std::vector<std::string> links() const;

  // Places the parts (T_tanker_link for every link in links()) and the eyes [m, tanker frame].
  // Returns true when the volumes were rebuilt, false when nothing moved. Throws
  // std::invalid_argument naming a missing link or a part an eye is inside of.
  bool Update(const std::map<std::string, Eigen::Isometry3d>& T_tanker_links,
              const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye);
  bool ready() const { return ready_; }

  // is_boom[i] for points in the tanker frame. Requires ready().
  std::vector<bool> Cull(const std::vector<Eigen::Vector3d>& points, CullMethod method) const;
  // Per point: which eyes the boom does not hide it from.
  std::vector<Visibility> Classify(const std::vector<Eigen::Vector3d>& points) const;
  // Per point and eye: hidden by the boom. eye 0 left, 1 right.
  bool Hidden(const Eigen::Vector3d& point, int eye) const;

  const std::vector<BoomPart>& parts() const { return parts_; }
  const Eigen::Isometry3d& T_tanker_part(size_t part) const { return T_tanker_parts_[part]; }
  const Eigen::Vector3d& eye(int e) const { return eyes_[e]; }
  const PartView& view(int eye, size_t part) const { return views_[eye][part]; }  // part frame
  const std::vector<ConvexVolume>& shadows(int eye) const { return shadows_[eye]; }
  // Per part, in the tanker frame: the grown part's view cone from the left eye, the planes
  // that cut it at the far side (empty with cull_behind_boom), and the outline's cone.
  struct CullVolume {
    ConvexVolume cone, far_side, outline;
    // `p_toward_eye`: p moved toward the left eye by its depth margin (TowardEye), for the far
    // side.
    bool Contains(const Eigen::Vector3d& p, const Eigen::Vector3d& p_toward_eye) const;
  };
  const std::vector<CullVolume>& cull_volumes() const { return cull_; }

 private:
  bool Moved(const std::map<std::string, Eigen::Isometry3d>& T_tanker_links,
             const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye) const;
  // The posed grown (or outline) boom for the ray tests.
  struct RayTarget {
    std::vector<Eigen::Matrix3d> triangles;  // columns: v0, v1 - v0, v2 - v0
    std::unique_ptr<aar_geometry::VisibilityTester> bvh;
    bool HitsBrute(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
    void Build(const aar_geometry::TriangleMesh& mesh);
  };
  void BuildRayTargets() const;  // on first use: only the ray methods need them
  // p moved toward the left eye along its ray by cull_depth_coefficient * range^2 (p when 0).
  Eigen::Vector3d TowardEye(const Eigen::Vector3d& p) const;

  std::vector<BoomPart> parts_;
  BoomOcclusionOptions options_;
  bool ready_ = false;
  std::map<std::string, Eigen::Isometry3d> T_tanker_links_;
  Eigen::Vector3d eyes_[2];
  std::vector<Eigen::Isometry3d> T_tanker_parts_;
  std::vector<PartView> views_[2];
  std::vector<ConvexVolume> shadows_[2];
  std::vector<CullVolume> cull_;
  mutable RayTarget grown_, outline_;
  mutable bool ray_targets_built_ = false;
  aar_geometry::TriangleMesh grown_boom_, outline_boom_;  // tanker frame
};

}  // namespace aar_occlusion
