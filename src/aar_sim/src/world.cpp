#include "aar_sim/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <aar_geometry/mesh_io.h>

#include <aar_description/boom_model.h>

namespace aar_sim {

using aar_description::BoomJointPositions;
namespace {

// The renderer sees the rig's rectified view, grown by `margin` [px] on each side for raw
// cameras whose lenses look beyond it.
RendererOptions WithRigIntrinsics(RendererOptions renderer, const StereoRig& rig,
                                  const Eigen::Vector2i& margin) {
  renderer.intrinsics = rig.intrinsics;
  renderer.intrinsics.width += 2 * margin.x();
  renderer.intrinsics.height += 2 * margin.y();
  renderer.intrinsics.cx += margin.x();
  renderer.intrinsics.cy += margin.y();
  return renderer;
}

std::unique_ptr<RawCamera> MakeRaw(const WorldOptions& o, const LensOptions& lens,
                                   const std::string& side) {
  if (!o.raw.enabled) return nullptr;
  try {
    return std::make_unique<RawCamera>(o.rig.intrinsics, lens);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(side + " camera (" + side + "_distortion, " + side +
                                "_rotation_deg): " + e.what());
  }
}

Eigen::Vector2i ViewMargin(const RawCamera* left, const RawCamera* right) {
  if (!left) return Eigen::Vector2i::Zero();
  return {std::max(left->margin_x(), right->margin_x()),
          std::max(left->margin_y(), right->margin_y())};
}

// The rig's view from the renderer's grown one.
template <typename T>
Image<T> Crop(const Image<T>& image, const Eigen::Vector2i& margin) {
  if (image.data.empty() || margin.isZero()) return image;
  Image<T> out;
  out.width = image.width - 2 * margin.x();
  out.height = image.height - 2 * margin.y();
  out.data.reserve(static_cast<size_t>(out.width) * out.height);
  for (int v = 0; v < out.height; ++v) {
    const T* row = &image.at(margin.x(), v + margin.y());
    out.data.insert(out.data.end(), row, row + out.width);
  }
  return out;
}

void CropView(RenderedView& view, const Eigen::Vector2i& margin) {
  view.radiance = Crop(view.radiance, margin);
  view.image = Crop(view.image, margin);
  view.label = Crop(view.label, margin);
  view.depth = Crop(view.depth, margin);
}

}  // namespace

WorldOptions DefaultWorldOptions(const std::string& models_dir) {
  WorldOptions o;
  o.receiver = aar_description::LoadReceiverDescription(models_dir + "/c12.yaml");
  o.boom_urdf = models_dir + "/boom.urdf";
  o.urdf.package_paths = {models_dir + "/../.."};
  o.rig = MakeStereoRig(CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0), 0.5);
  return o;
}

World::World(const WorldOptions& options)
    : options_(options),
      receiver_(aar_description::LoadReceiverMesh(options.receiver)),
      boom_(aar_geometry::LoadRobotModel(options.boom_urdf, options.urdf)),
      raw_left_(MakeRaw(options, options.raw.left, "left")),
      raw_right_(MakeRaw(options, options.raw.right, "right")),
      view_margin_(ViewMargin(raw_left_.get(), raw_right_.get())),
      renderer_(WithRigIntrinsics(options.renderer, options.rig, view_margin_)) {
  options_.renderer.intrinsics = options_.rig.intrinsics;
  options_.sensor.Validate();
  for (const Eigen::Vector3d& p : receiver_.vertices) receiver_box_.extend(p);
  for (const auto& link : boom_.links) {
    Eigen::AlignedBox3d box;
    for (const auto& visual : link.visuals)
      for (const Eigen::Vector3d& p : visual.mesh.vertices) box.extend(visual.T_link_geometry * p);
    if (!box.isEmpty()) link_boxes_.emplace_back(link.name, box);
  }
  receiver_handle_ = renderer_.AddMesh(
      receiver_, Label::kReceiver, Surface::kAircraftPaint,
      options.receiver.has_canopy ? options.receiver.canopy : Eigen::AlignedBox3d());
  for (const auto& link : boom_.links) {
    for (const auto& visual : link.visuals) {
      boom_elements_.push_back({renderer_.AddMesh(visual.mesh, Label::kBoom, Surface::kBoomStripes),
                                link.name, visual.T_link_geometry});
    }
  }
  if (raw_left_) {
    raw_left_->SetViewMargin(view_margin_.x(), view_margin_.y());
    raw_right_->SetViewMargin(view_margin_.x(), view_margin_.y());
  }
}

StereoFrame World::Render(const FlightPathRow& row, const BoomPose& boom, uint64_t frame_index,
                          bool want_label, bool want_depth, const SceneState* exposure_end) {
  return RenderRig(options_.rig, 0, row, boom, frame_index, want_label, want_depth, exposure_end);
}

StereoFrame World::RenderRig(const StereoRig& rig, uint64_t stream, const FlightPathRow& row,
                             const BoomPose& boom, uint64_t frame_index, bool want_label,
                             bool want_depth, const SceneState* exposure_end) {
  CheckIntrinsics(rig);
  StereoFrame frame;
  frame.T_tanker_receiver = row.T_tanker_receiver();
  frame.boom = boom;
  frame.T_tanker_links = aar_geometry::ComputeLinkPoses(boom_, BoomJointPositions(boom));
  std::vector<DrawItem> items = {{receiver_handle_, frame.T_tanker_receiver}};
  if (options_.boom_visible) {
    for (const auto& e : boom_elements_) {
      items.push_back({e.mesh, frame.T_tanker_links.at(e.link) * e.T_link_geometry});
    }
  }
  // The sensor (sensor.h) makes each view's mono8 image from its radiance; motion blur needs the
  // label and depth too.
  const SensorOptions& sensor = options_.sensor;
  const bool blur = sensor.motion_blur && exposure_end;
  const Eigen::Isometry3d T_tanker_left = rig.T_tanker_left_optical,
                          T_tanker_right = rig.T_tanker_right_optical();
  const std::vector<PropellerItem> propellers = Propellers(row);
  frame.left =
      renderer_.Render(T_tanker_left, items, want_label || blur, want_depth || blur, propellers);
  frame.right =
      renderer_.Render(T_tanker_right, items, want_label || blur, want_depth || blur, propellers);
  const double gain = ExposureGain(sensor, frame.left.radiance);  // one for the pair
  for (int camera = 0; camera < 2; ++camera) {
    RenderedView& view = camera == 0 ? frame.left : frame.right;
    ViewMotion motion;
    if (blur) motion = Motion(camera == 0 ? T_tanker_left : T_tanker_right, frame, *exposure_end);
    SensorInput input;
    input.radiance = &view.radiance;
    input.label = &view.label;
    input.depth = &view.depth;
    input.motion = blur ? &motion : nullptr;
    input.camera = camera;
    input.view_key = 2 * frame_index + camera + (stream << 40);  // rig 0: 2 frame + camera
    input.exposure_gain = gain;
    view.image = Expose(sensor, input);
    if (!want_label) view.label = {};
    if (!want_depth) view.depth = {};
  }
  if (raw_left_) {
    frame.left_raw = raw_left_->Distort(frame.left.image);
    frame.right_raw = raw_right_->Distort(frame.right.image);
    CropView(frame.left, view_margin_);
    CropView(frame.right, view_margin_);
  }
  return frame;
}

void World::CheckIntrinsics(const StereoRig& rig) const {
  const CameraIntrinsics &theirs = rig.intrinsics, &mine = options_.rig.intrinsics;
  if (theirs.width != mine.width || theirs.height != mine.height || theirs.fx != mine.fx ||
      theirs.fy != mine.fy || theirs.cx != mine.cx || theirs.cy != mine.cy) {
    throw std::invalid_argument("a rig's cameras must have the world's intrinsics");
  }
}

double ViewVisibility::fraction() const {
  return silhouette_px > 0 ? static_cast<double>(visible_px) / silhouette_px
                           : std::numeric_limits<double>::quiet_NaN();
}

namespace {

// The receiver's pixels in `alone` (drawn by itself) and, of those, the ones `scene` does not
// give to the boom.
ViewVisibility CountVisible(const Image<uint8_t>& alone, const Image<uint8_t>& scene) {
  if (alone.data.size() != scene.data.size()) {
    throw std::logic_error("visibility: the receiver's label is not the frame's size");
  }
  ViewVisibility v;
  for (size_t i = 0; i < alone.data.size(); ++i) {
    if (alone.data[i] != static_cast<uint8_t>(Label::kReceiver)) continue;
    ++v.silhouette_px;
    if (scene.data[i] != static_cast<uint8_t>(Label::kBoom)) ++v.visible_px;
  }
  return v;
}

}  // namespace

std::array<ViewVisibility, 2> World::MeasureVisibility(const StereoFrame& frame) {
  return MeasureVisibility(frame, options_.rig);
}

std::array<ViewVisibility, 2> World::MeasureVisibility(const StereoFrame& frame,
                                                       const StereoRig& rig) {
  if (frame.left.label.data.empty() || frame.right.label.data.empty()) {
    throw std::invalid_argument("visibility needs the frame's label (render it with want_label)");
  }
  const std::vector<DrawItem> receiver_alone = {{receiver_handle_, frame.T_tanker_receiver}};
  std::array<ViewVisibility, 2> out;
  for (int camera = 0; camera < 2; ++camera) {
    const Eigen::Isometry3d T =
        camera == 0 ? rig.T_tanker_left_optical : rig.T_tanker_right_optical();
    out[camera] = CountVisible(Crop(renderer_.RenderLabel(T, receiver_alone), view_margin_),
                               camera == 0 ? frame.left.label : frame.right.label);
  }
  return out;
}

std::array<ViewVisibility, 2> World::MeasureVisibility(const FlightPathRow& row,
                                                       const BoomPose& boom, const StereoRig& rig) {
  CheckIntrinsics(rig);
  const std::vector<DrawItem> receiver_alone = {{receiver_handle_, row.T_tanker_receiver()}};
  std::vector<DrawItem> scene = receiver_alone;
  if (options_.boom_visible) {
    const auto links = aar_geometry::ComputeLinkPoses(boom_, BoomJointPositions(boom));
    for (const auto& e : boom_elements_) {
      scene.push_back({e.mesh, links.at(e.link) * e.T_link_geometry});
    }
  }
  std::array<ViewVisibility, 2> out;
  for (int camera = 0; camera < 2; ++camera) {
    const Eigen::Isometry3d T =
        camera == 0 ? rig.T_tanker_left_optical : rig.T_tanker_right_optical();
    out[camera] = CountVisible(Crop(renderer_.RenderLabel(T, receiver_alone), view_margin_),
                               Crop(renderer_.RenderLabel(T, scene), view_margin_));
  }
  return out;
}

std::vector<PropellerItem> World::Propellers(const FlightPathRow& row) const {
  std::vector<PropellerItem> out;
  if (options_.propellers == PropellerMode::kNone) return out;
  const Eigen::Isometry3d T_tanker_receiver = row.T_tanker_receiver();
  for (const aar_description::PropellerDescription& p : options_.receiver.propellers) {
    // The disc's frame: x along the axis, y and z across it.
    const Eigen::Vector3d x = p.axis.normalized();
    const Eigen::Vector3d any =
        std::abs(x.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d y = any.cross(x).normalized();
    Eigen::Isometry3d T_body_disc = Eigen::Isometry3d::Identity();
    T_body_disc.linear() << x, y, x.cross(y);
    T_body_disc.translation() = p.hub;
    const double omega = p.rpm * 2.0 * M_PI / 60.0;  // [rad/s]
    PropellerItem item;
    item.T_tanker_disc = T_tanker_receiver * T_body_disc;
    item.radius_m = p.radius;
    item.hub_radius_m = p.hub_radius;
    item.chord_m = p.chord;
    item.blades = p.blades;
    // The turn at path time t, reduced first so that long paths keep the angle's precision.
    item.angle_rad = p.phase_deg * M_PI / 180.0 + std::fmod(omega * row.t, 2.0 * M_PI);
    item.swept_rad = options_.propellers == PropellerMode::kDisc ? 2.0 * M_PI
                     : options_.sensor.motion_blur ? std::abs(omega) * options_.sensor.exposure_time
                                                   : 0.0;
    if (omega < 0.0) item.angle_rad -= item.swept_rad;  // the same arc, swept backwards
    out.push_back(item);
  }
  return out;
}

ViewMotion World::Motion(const Eigen::Isometry3d& T_tanker_optical, const StereoFrame& start,
                         const SceneState& end) const {
  ViewMotion motion;
  motion.intrinsics = renderer_.options().intrinsics;
  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical.inverse();
  // A body at T_tanker_body at the start and T_tanker_body_end at the end.
  auto body = [&](const Eigen::Isometry3d& T_tanker_body,
                  const Eigen::Isometry3d& T_tanker_body_end, const Eigen::AlignedBox3d& box) {
    BodyMotion b;
    b.T_end_start =
        T_optical_tanker * T_tanker_body_end * T_tanker_body.inverse() * T_tanker_optical;
    b.T_body_optical = T_tanker_body.inverse() * T_tanker_optical;
    b.box_in_body = box;
    return b;
  };
  // A label whose bodies all keep still is left out, so that a frame without motion costs nothing;
  // otherwise every body of it stays in, so that a still link's pixels keep still.
  const Eigen::Isometry3d T_tanker_receiver_end = end.row.T_tanker_receiver();
  if (!T_tanker_receiver_end.isApprox(start.T_tanker_receiver, 1e-15)) {
    motion.bodies.emplace_back(Label::kReceiver,
                               body(start.T_tanker_receiver, T_tanker_receiver_end, receiver_box_));
  }
  if (options_.boom_visible) {
    const auto T_tanker_links_end =
        aar_geometry::ComputeLinkPoses(boom_, BoomJointPositions(end.boom));
    bool moves = false;
    for (const auto& [link, box] : link_boxes_)
      moves |= !T_tanker_links_end.at(link).isApprox(start.T_tanker_links.at(link), 1e-15);
    if (moves) {
      for (const auto& [link, box] : link_boxes_) {
        motion.bodies.emplace_back(
            Label::kBoom, body(start.T_tanker_links.at(link), T_tanker_links_end.at(link), box));
      }
    }
  }
  return motion;
}

}  // namespace aar_sim
