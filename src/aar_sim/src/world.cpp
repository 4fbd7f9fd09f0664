#include "aar_sim/world.h"

#include <aar_geometry/mesh_io.h>

#include <aar_description/boom_model.h>

namespace aar_sim {

using aar_description::BoomJointPositions;
namespace {

RendererOptions WithRigIntrinsics(RendererOptions renderer, const StereoRig& rig) {
  renderer.intrinsics = rig.intrinsics;
  return renderer;
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
      renderer_(WithRigIntrinsics(options.renderer, options.rig)) {
  options_.renderer.intrinsics = options_.rig.intrinsics;
  receiver_handle_ = renderer_.AddMesh(receiver_, Label::kReceiver, Surface::kAircraftPaint);
  for (const auto& link : boom_.links) {
    for (const auto& visual : link.visuals) {
      boom_elements_.push_back({renderer_.AddMesh(visual.mesh, Label::kBoom, Surface::kBoomStripes),
                                link.name, visual.T_link_geometry});
    }
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
  return frame;
}

}  // namespace aar_sim
