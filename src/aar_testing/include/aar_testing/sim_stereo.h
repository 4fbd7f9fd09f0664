#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_geometry/robot_model.h>
#include <aar_sim/flight_path.h>
#include <aar_sim/world.h>
#include <aar_stereo/stereo.h>
#include <aar_testing/paths.h>
#include <opencv2/core.hpp>

namespace aar_testing {

// One simulated frame through aar_stereo: the render, the stereo result and its points in the
// tanker frame (one per cloud point, in cloud order).
struct SimStereoFrame {
  aar_sim::StereoFrame rendered;
  aar_stereo::StereoResult stereo;
  std::vector<Eigen::Vector3d> points_in_tanker;  // [m]
};

// The "render a frame, run stereo, points into the tanker frame" set-up that benches and tests
// share: the shipped world (or one given) and aar_stereo with the given options.
class SimStereo {
 public:
  explicit SimStereo(const aar_sim::WorldOptions& world = DefaultWorld(),
                     const aar_stereo::StereoOptions& stereo = {});

  static aar_sim::WorldOptions DefaultWorld();  // aar_sim::DefaultWorldOptions(ModelsDir())

  SimStereoFrame Run(const aar_sim::FlightPathRow& row, const aar_description::BoomPose& boom,
                     uint64_t frame_index, bool with_label = false, bool with_depth = false);
  // The rendered pair as views (no copy) for aar_stereo or stereo_image_proc.
  cv::Mat Left(const aar_sim::StereoFrame& frame) const;
  cv::Mat Right(const aar_sim::StereoFrame& frame) const;
  std::vector<Eigen::Vector3d> ToTanker(const aar_stereo::CloudPoints& cloud) const;

  aar_sim::World& world() { return world_; }
  const aar_sim::WorldOptions& world_options() const { return options_; }
  const aar_sim::StereoRig& rig() const { return options_.rig; }
  const aar_stereo::StereoGeometry& geometry() const { return geometry_; }
  const aar_stereo::StereoProcessor& stereo() const { return stereo_; }
  Eigen::Vector3d left_eye() const { return rig().T_tanker_left_optical.translation(); }
  Eigen::Vector3d right_eye() const { return rig().T_tanker_right_optical().translation(); }

 private:
  aar_sim::WorldOptions options_;
  aar_sim::World world_;
  aar_stereo::StereoGeometry geometry_;
  aar_stereo::StereoProcessor stereo_;
};

}  // namespace aar_testing
