#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// Points on the receiver's surface in the receiver frame, with normals and part labels.
struct ReferenceCloud {
  std::vector<Eigen::Vector3d> points;   // [m]
  std::vector<Eigen::Vector3d> normals;  // unit, outward
  std::vector<int> parts;                // index into part_names
  std::vector<std::string> part_names;

  size_t size() const { return points.size(); }
  // The subset whose part is one of `parts`; throws std::invalid_argument for an unknown part.
  ReferenceCloud Select(const std::vector<std::string>& parts) const;
  // The subset where keep[i] is true.
  ReferenceCloud Subset(const std::vector<bool>& keep) const;
};

struct ReferenceModelOptions {
  double points_per_m2 = 400.0;  // [1/m^2] dense sampling: about 5 cm spacing, 63k points
  uint64_t seed = 1;
  double visibility_tolerance =
      0.01;  // [m] a sample is seen if nothing is hit before it, less this
};

// Seeded, area-weighted dense sampling of the receiver mesh.
ReferenceCloud SampleReceiver(const TriangleMesh& receiver, const ReferenceModelOptions& options);

// Line-of-sight tests against a triangle mesh through an Embree BVH (built once).
class VisibilityTester {
 public:
  explicit VisibilityTester(const TriangleMesh& mesh);  // throws std::runtime_error
  ~VisibilityTester();
  VisibilityTester(const VisibilityTester&) = delete;
  VisibilityTester& operator=(const VisibilityTester&) = delete;

  // visible[i]: the segment from `eye` to points[i] (both in the mesh frame) hits nothing closer
  // than `tolerance` [m] to points[i], and the point's normal faces the eye.
  std::vector<bool> Visible(const std::vector<Eigen::Vector3d>& points,
                            const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& eye,
                            double tolerance) const;

  // hit[i]: the ray from origins[i] along directions[i] (unit) hits the mesh.
  std::vector<bool> RaysHit(const std::vector<Eigen::Vector3d>& origins,
                            const std::vector<Eigen::Vector3d>& directions) const;

 private:
  struct Bvh;
  std::unique_ptr<Bvh> bvh_;
};

// The shelled model (thesis Fig. 10): the samples every eye sees, eyes given in the receiver
// frame (the cameras at a nominal approach pose).
ReferenceCloud Shell(const ReferenceCloud& dense, const VisibilityTester& receiver,
                     const std::vector<Eigen::Vector3d>& eyes_in_receiver, double tolerance);

// The thesis's seed for T_tanker_receiver: the tanker's orientation, and a position that puts the
// reference model's centroid on the sensed points' centroid (points in the tanker and receiver
// frames). Throws std::invalid_argument for an empty cloud.
Eigen::Isometry3d CentroidSeed(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                               const std::vector<Eigen::Vector3d>& reference_in_receiver);

// The points in the densest ball of radius `radius` [m] (not in the thesis; the points a robust
// centroid seed takes): its centre is the candidate (up to `candidates` points, evenly spaced
// through the cloud) with the most points within `radius`, then moved by mean shift (at most 5
// steps) to the centroid of the points it holds. Clutter scattered over hundreds of metres (far
// background texture that block matching mismatched into range) falls outside a ball of the
// receiver's size. Deterministic. Throws std::invalid_argument for an empty cloud, radius <= 0
// or candidates < 1.
std::vector<Eigen::Vector3d> DensestBall(const std::vector<Eigen::Vector3d>& points, double radius,
                                         int candidates = 256);

// Which sensed points a centroid seed takes (occlusion's predicted pose without an estimate,
// registration's seed): all (thesis), or those in the densest ball of the reference's size
// (DensestBall; ours), which far clutter does not drag.
enum class SeedPoints { kAll, kDensestBall };

// Half the diagonal of the points' bounding box [m]: the radius of a ball that holds a model
// centred on it (0 for fewer than two points).
double HalfDiagonal(const std::vector<Eigen::Vector3d>& points);

}  // namespace aar_geometry
