#include "aar_sim/world.h"

#include <algorithm>
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
  receiver_handle_ = renderer_.AddMesh(receiver_, Label::kReceiver, Surface::kAircraftPaint);
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
                          bool want_label, bool want_depth) {
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
  frame.left = renderer_.Render(options_.rig.T_tanker_left_optical, items, 2 * frame_index,
                                want_label, want_depth);
  frame.right = renderer_.Render(options_.rig.T_tanker_right_optical(), items, 2 * frame_index + 1,
                                 want_label, want_depth);
  if (raw_left_) {
    frame.left_raw = raw_left_->Distort(frame.left.image);
    frame.right_raw = raw_right_->Distort(frame.right.image);
    CropView(frame.left, view_margin_);
    CropView(frame.right, view_margin_);
  }
  return frame;
}

}  // namespace aar_sim
