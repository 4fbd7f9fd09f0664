#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/triangle_mesh.h>

#include "aar_occlusion/boom.h"
#include "aar_occlusion/dynamic_reference.h"

namespace aar_occlusion {

// A propeller disc of the receiver (its description's `propellers`), receiver frame.
struct PropellerDisc {
  Eigen::Vector3d hub = Eigen::Vector3d::Zero();    // [m] the disc's centre
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit
  double radius = 1.25;                             // [m] blade tip
  double hub_radius = 0.17;                         // [m] spinner
};

struct OcclusionStepOptions {
  // false: the tanker flies no boom (a receiver-only rig, or the boom hidden to measure what it
  // costs): nothing is culled and the reference accounts for the receiver's self-occlusion only.
  bool model_boom = true;
  CullMethod cull = CullMethod::kVolumes;  // how boom points leave the sensed cloud
  BoomPartsOptions parts;                  // the cull and silhouette margins
  BoomOcclusionOptions boom;               // cull_behind_boom: the thesis's whole-ray test
  bool build_reference = true;             // the dynamic reference model, each frame
  // 127 samples per m^2 (about 9 cm apart, 20k samples): as accurate as 400 on the default
  // approach (docs/RESULTS.md) at a third of the cost (docs/PERFORMANCE.md).
  aar_geometry::ReferenceModelOptions sampling = [] {
    aar_geometry::ReferenceModelOptions o;
    o.points_per_m2 = 127.0;
    return o;
  }();
  DynamicReferenceOptions reference;
  // [m] points farther than this from the left eye are no measurement (the stereo stage cuts at
  // 750 m, as the thesis): dropped from the cloud before anything else sees them.
  double max_point_range = 1000.0;
  // The predicted pose before any estimate: the centroid of the kept points (kAll, thesis), or of
  // those in the densest ball of the receiver's size (kDensestBall; ours). Registration's
  // seed_points, the same choice.
  aar_geometry::SeedPoints seed_points = aar_geometry::SeedPoints::kAll;
  // Spinning propellers (not in the thesis): with an estimate to place them, the points seen
  // through a disc (a ray from the left eye crossing it between hub_radius + margin and
  // radius + margin) within propeller_depth_margin of it along the ray leave the cloud as the
  // boom's do. The reference keeps what lies behind the discs (see-through: a blade covers a
  // disc point a tenth to a quarter of the time).
  bool cull_propellers = false;
  std::vector<PropellerDisc> propellers;
  double propeller_margin = 0.1;        // [m] radial, at the tip and the spinner
  double propeller_depth_margin = 0.5;  // [m] along the ray, either side of the disc
  // Receiver gate (not in the thesis): with an estimate, points that are not boom and lie outside
  // the receiver's bounding box at the estimate's pose, grown by gate_margin, are no receiver:
  // dropped (counted in `gated`, in neither list). They are far background that block matching
  // mismatched into range, which the 750 m cut keeps (docs/realism/README.md), and other clutter.
  // The margin covers the estimate's age and error: it is the previous frame's pose, unmoved. Along
  // the camera ray a point may also lie gate_depth_coefficient * range^2 short of or beyond the
  // grown box: stereo's depth error (for a disparity error e on a rig of focal length f and
  // baseline B, e / (f B) * range^2; 0.0009 is half a pixel on the shipped rig, 9 m at 100 m, 1.2 m
  // at 36 m).
  bool gate_receiver = false;
  double gate_margin = 3.0;                // [m] the box grown on every side
  double gate_depth_coefficient = 0.0009;  // [1/m]
};

// What the ROS layer gathered for one sensed cloud, all in the tanker frame.
struct OcclusionInput {
  std::vector<Eigen::Vector3d> points;                  // [m] the cloud's finite points
  Eigen::Vector3d left_eye = Eigen::Vector3d::Zero();   // [m]
  Eigen::Vector3d right_eye = Eigen::Vector3d::Zero();  // [m]
  // T_tanker_link of every link in boom_links() when NeedsLinks(); a missing one leaves the frame
  // unculled, with `links_error` saying why.
  std::map<std::string, Eigen::Isometry3d> T_tanker_links;
  std::string links_error;
  // The predicted pose (the latest estimate); without one, the thesis's seed: the kept points'
  // centroid and the tanker's orientation.
  std::optional<Eigen::Isometry3d> T_tanker_receiver_predicted;
  bool volumes_wanted = false;  // someone shows the shadow volumes: place the boom for them
};

struct OcclusionResult {
  std::vector<size_t> kept, removed;  // indices into OcclusionInput::points
  size_t out_of_range = 0;            // points in neither: beyond max_point_range (or not finite)
  size_t propeller_points = 0;        // of `removed`: on the propeller discs (cull_propellers)
  size_t gated = 0;          // in neither list: outside the receiver's grown box (gate_receiver)
  bool boom_placed = false;  // the volumes are this frame's (culled as configured)
  bool volumes_rebuilt = false;  // the boom or an eye moved: the volumes changed
  std::string cull_error;        // why the frame passes through unculled; empty if it did not
  bool has_reference = false;
  DynamicReferenceResult reference;  // receiver frame, at T_tanker_receiver
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();  // the pose it was built at
  std::string reference_error;  // why there is no reference; empty if there is one or none wanted
};

// The occlusion stage per sensed cloud (thesis 3.7-3.8): boom points out of the cloud by the
// boom's volumes, and the dynamic reference model at the predicted pose. A boom model that was
// refused or links that cannot be placed leave frames unculled (the reference then accounts for
// self-occlusion only); the result says why.
class OcclusionStep {
 public:
  // `boom`: the boom's robot model, or nullopt with `boom_error` saying why there is none.
  // `receiver`: needed when options.build_reference. Throws std::invalid_argument for a receiver
  // that cannot be sampled; a boom whose parts are refused is recorded in boom_error().
  OcclusionStep(const OcclusionStepOptions& options,
                const std::optional<aar_geometry::RobotModel>& boom, std::string boom_error,
                const aar_geometry::TriangleMesh* receiver);
  ~OcclusionStep();

  // The links whose poses Process needs this frame (none when the boom was refused or nothing
  // would use it).
  bool NeedsLinks(bool volumes_wanted) const;
  std::vector<std::string> boom_links() const;
  bool builds_reference() const { return reference_ != nullptr; }

  OcclusionResult Process(const OcclusionInput& input);

  const OcclusionStepOptions& options() const { return options_; }
  const BoomOcclusion* boom() const { return boom_.get(); }  // null when refused
  const std::string& boom_error() const { return boom_error_; }
  size_t reference_samples() const { return reference_ ? reference_->size() : 0; }

 private:
  // Culling, the reference or someone showing the volumes needs the boom placed.
  bool UsesBoom(bool volumes_wanted) const;
  // Process's steps, in order, over the points in range.
  void PlaceBoom(const OcclusionInput& in, OcclusionResult* r);
  void SplitBoomAndGate(const std::vector<Eigen::Vector3d>& points, const OcclusionInput& in,
                        OcclusionResult* r);
  void CullPropellers(const std::vector<Eigen::Vector3d>& points, const OcclusionInput& in,
                      OcclusionResult* r) const;
  void BuildReference(const std::vector<Eigen::Vector3d>& points, const OcclusionInput& in,
                      OcclusionResult* r);

  OcclusionStepOptions options_;
  std::unique_ptr<BoomOcclusion> boom_;
  std::string boom_error_;  // why boom_ is null, naming the link
  std::unique_ptr<DynamicReference> reference_;
  double receiver_radius_ = 0.0;      // [m] half the receiver's box diagonal (kDensestBall)
  Eigen::AlignedBox3d receiver_box_;  // [m] receiver frame, grown by gate_margin (gate_receiver)
};

}  // namespace aar_occlusion
