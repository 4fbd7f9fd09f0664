#include "aar_testing/sim_stereo.h"

namespace aar_testing {
aar_sim::WorldOptions SimStereo::DefaultWorld() {
  return aar_sim::DefaultWorldOptions(ModelsDir());
}

SimStereo::SimStereo(const aar_sim::WorldOptions& world, const aar_stereo::StereoOptions& stereo)
    : options_(world),
      world_(world),
      geometry_(aar_stereo::StereoGeometry::Rectified(
          world.rig.intrinsics.width, world.rig.intrinsics.height, world.rig.intrinsics.fx,
          world.rig.intrinsics.fy, world.rig.intrinsics.cx, world.rig.intrinsics.cy,
          world.rig.baseline)),
      stereo_(stereo) {}

cv::Mat SimStereo::Left(const aar_sim::StereoFrame& frame) const {
  const auto& k = options_.rig.intrinsics;
  return cv::Mat(k.height, k.width, CV_8UC1, const_cast<uint8_t*>(frame.left.image.data.data()));
}

cv::Mat SimStereo::Right(const aar_sim::StereoFrame& frame) const {
  const auto& k = options_.rig.intrinsics;
  return cv::Mat(k.height, k.width, CV_8UC1, const_cast<uint8_t*>(frame.right.image.data.data()));
}

std::vector<Eigen::Vector3d> SimStereo::ToTanker(const aar_stereo::CloudPoints& cloud) const {
  std::vector<Eigen::Vector3d> points;
  points.reserve(cloud.xyz.size());
  for (const auto& p : cloud.xyz)
    points.push_back(options_.rig.T_tanker_left_optical * p.cast<double>());
  return points;
}

SimStereoFrame SimStereo::Run(const aar_sim::FlightPathRow& row,
                              const aar_description::BoomPose& boom, uint64_t frame_index,
                              bool with_label, bool with_depth) {
  SimStereoFrame f;
  f.rendered = world_.Render(row, boom, frame_index, with_label, with_depth);
  f.stereo = stereo_.Process(Left(f.rendered), Right(f.rendered), geometry_);
  f.points_in_tanker = ToTanker(f.stereo.cloud);
  return f;
}

}  // namespace aar_testing
