#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>

#include "aar_sim/flight_path.h"
#include "aar_sim/raw_camera.h"
#include "aar_sim/renderer.h"
#include "aar_sim/sensor.h"

namespace aar_sim {

// How the receiver description's propellers are drawn (issue 16, docs/realism/sun.md).
enum class PropellerMode {
  kNone = 0,    // not drawn (the thesis's world)
  kBlades = 1,  // blades at the shutter: smeared over the exposure when motion_blur is on
  kDisc = 2,    // the fully blurred disc (a long exposure's average)
};

struct WorldOptions {
  aar_description::ReceiverDescription receiver;  // mesh, its scale and datum
  std::string boom_urdf;                          // boom URDF; its root link is the tanker frame
  aar_geometry::RobotModelOptions urdf;
  StereoRig rig;             // its intrinsics are the renderer's
  RendererOptions renderer;  // intrinsics are taken from the rig
  bool boom_visible = true;
  RawCameraOptions raw;  // enabled: also the raw (distorted, unrectified) images
  SensorOptions sensor;  // radiance to mono8 (defaults: the ideal camera)
  PropellerMode propellers = PropellerMode::kNone;
};

// The shipped world: the C-12 (c12.yaml) and boom.urdf from `models_dir` (aar_description's
// models/, whose parent's parent holds aar_description for package:// look-ups) and the default rig
// (1280x960, 60 deg, 0.5 m baseline, the default mount of docs/ARCHITECTURE.md). Renderer options
// stay at their defaults.
WorldOptions DefaultWorldOptions(const std::string& models_dir);

// The scene at a time: the receiver's path row and the boom's pose.
struct SceneState {
  FlightPathRow row;
  BoomPose boom;
};

// One rendered stereo pair with the truth that produced it.
struct StereoFrame {
  RenderedView left, right;  // the ideal rectified pinhole views (the rig's size)
  // raw.enabled: what the real cameras would deliver (RawCamera::Distort of the views above)
  Image<uint8_t> left_raw, right_raw;
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  BoomPose boom;
  std::map<std::string, Eigen::Isometry3d> T_tanker_links;  // boom links
};

// What the boom leaves of the receiver's silhouette in one camera's view (docs/AVAILABILITY.md):
// a frame with little to see is missed by physics, not by the estimator.
struct ViewVisibility {
  int silhouette_px = 0;  // pixels of the receiver drawn alone, inside the view
  int visible_px = 0;     // of those, the ones the boom does not cover
  // visible_px / silhouette_px; NaN when the receiver is not in the view at all.
  double fraction() const;
};

// The virtual world: receiver and boom models, the stereo rig and the renderer.
class World {
 public:
  // Throws aar_geometry::LoadError for a model that does not load or fails the receiver checks
  // (aar_description::LoadReceiverMesh), RenderError without EGL, std::invalid_argument for
  // sensor options out of range.
  explicit World(const WorldOptions& options);

  // The pair at (row, boom), the state at the exposure's start (the truth). `exposure_end`: the
  // state at its end, for motion blur (options.sensor.motion_blur); null: nothing moves.
  StereoFrame Render(const FlightPathRow& row, const BoomPose& boom, uint64_t frame_index,
                     bool want_label = false, bool want_depth = false,
                     const SceneState* exposure_end = nullptr);
  // The same from another rig's cameras (a second rig: lenses, sensor and intrinsics are the
  // world's; std::invalid_argument for other intrinsics). `stream` (1, 2, ...) keeps the rig's
  // noise apart from the world's own rig's (0: Render's).
  StereoFrame RenderRig(const StereoRig& rig, uint64_t stream, const FlightPathRow& row,
                        const BoomPose& boom, uint64_t frame_index, bool want_label = false,
                        bool want_depth = false, const SceneState* exposure_end = nullptr);

  // The visibility of the receiver in each view of `frame` (left, right): its silhouette drawn
  // alone against the frame's label. Throws std::invalid_argument when `frame` was rendered
  // without its label (Render's want_label).
  std::array<ViewVisibility, 2> MeasureVisibility(const StereoFrame& frame);
  // The same for a frame RenderRig rendered from `rig`.
  std::array<ViewVisibility, 2> MeasureVisibility(const StereoFrame& frame, const StereoRig& rig);
  // The same from another rig's cameras (left, right) at (row, boom), rendering only the labels:
  // what a mount would see before it flies (tools/mount_visibility). The rig's intrinsics must
  // be the world's (std::invalid_argument otherwise); for the world's own rig it equals the above.
  std::array<ViewVisibility, 2> MeasureVisibility(const FlightPathRow& row, const BoomPose& boom,
                                                  const StereoRig& rig);

  const WorldOptions& options() const { return options_; }
  const aar_geometry::TriangleMesh& receiver_mesh() const { return receiver_; }
  const aar_geometry::RobotModel& boom_model() const { return boom_; }
  // The propellers as drawn at `row` (empty unless options.propellers is on).
  std::vector<PropellerItem> Propellers(const FlightPathRow& row) const;
  Renderer& renderer() { return renderer_; }
  // The cameras' calibrations (null unless options.raw.enabled).
  const RawCamera* raw_left() const { return raw_left_.get(); }
  const RawCamera* raw_right() const { return raw_right_.get(); }

 private:
  struct BoomElement {
    int mesh;
    std::string link;
    Eigen::Isometry3d T_link_geometry;
  };
  WorldOptions options_;
  aar_geometry::TriangleMesh receiver_;
  aar_geometry::RobotModel boom_;
  // Before renderer_: raw cameras decide how far beyond the rig's view it renders.
  std::unique_ptr<RawCamera> raw_left_, raw_right_;
  Eigen::Vector2i view_margin_ = Eigen::Vector2i::Zero();  // [px] each side
  Renderer renderer_;
  int receiver_handle_ = -1;
  std::vector<BoomElement> boom_elements_;
  // Motion blur: the bodies' boxes in their own frames (receiver; boom links with visuals).
  Eigen::AlignedBox3d receiver_box_;
  std::vector<std::pair<std::string, Eigen::AlignedBox3d>> link_boxes_;
  ViewMotion Motion(const Eigen::Isometry3d& T_tanker_optical, const StereoFrame& start,
                    const SceneState& end) const;
  void CheckIntrinsics(const StereoRig& rig) const;  // throws unless the world's
};

}  // namespace aar_sim
