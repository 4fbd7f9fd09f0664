// On simulated frames through aar_stereo, boom culling against the simulator's label image:
// the points whose left pixel is labelled boom must go, those labelled receiver must stay.
#include <gtest/gtest.h>

#include <filesystem>

#include <aar_sim/boom_model.h>
#include <aar_sim/flight_path.h>
#include <aar_sim/world.h>
#include <aar_stereo/stereo.h>

#include "aar_occlusion/boom.h"

namespace aar_occlusion {
namespace {

struct Counts {
  int boom = 0, boom_culled = 0, receiver = 0, receiver_culled = 0, background = 0;
};

TEST(CullingOracle, RemovesBoomPointsAndKeepsReceiverPoints) {
  const std::string sim = AAR_SIM_SOURCE_DIR;
  const aar_sim::WorldOptions w = aar_sim::DefaultWorldOptions(sim + "/models");
  aar_sim::World world(w);
  const auto path =
      aar_sim::FlightPath::Load(sim + "/../../config/flight_paths/approach_default.csv");
  const aar_sim::CameraIntrinsics& k = w.rig.intrinsics;
  const auto g = aar_stereo::StereoGeometry::Rectified(k.width, k.height, k.fx, k.fy, k.cx, k.cy,
                                                       w.rig.baseline);
  const aar_stereo::StereoProcessor stereo{aar_stereo::StereoOptions{}};
  aar_geometry::RobotModelOptions urdf;
  urdf.package_paths = {std::filesystem::path(sim).parent_path().string()};
  const auto model = aar_geometry::LoadRobotModel(sim + "/models/boom.urdf", urdf);
  BoomOcclusion boom(LoadBoomParts(model));  // defaults: 10 cm near the boom, 2 cm outline
  BoomOcclusionOptions thesis_options;
  thesis_options.cull_behind_boom = true;  // the whole ray, as the thesis
  BoomOcclusion thesis(LoadBoomParts(model), thesis_options);

  const aar_sim::BoomPose poses[] = {aar_sim::DefaultBoomPose(),
                                     {33.0 * M_PI / 180.0, -8.0 * M_PI / 180.0, 1.0}};
  Counts total[3];  // volumes, rays (BVH), thesis (whole ray, volumes)
  const char* names[3] = {"volumes", "rays_bvh", "volumes, whole ray (thesis)"};
  for (const double t : {0.5, 5.0, 20.0, 32.0, 40.0, 46.0, 50.0}) {
    for (const auto& pose : poses) {
      const auto row = path.At(t);
      const auto frame = world.Render(row, pose, static_cast<uint64_t>(t * 10), true);
      const cv::Mat left(k.height, k.width, CV_8UC1,
                         const_cast<uint8_t*>(frame.left.image.data.data()));
      const cv::Mat right(k.height, k.width, CV_8UC1,
                          const_cast<uint8_t*>(frame.right.image.data.data()));
      const auto cloud = stereo.Process(left, right, g).cloud;
      std::vector<Eigen::Vector3d> points;
      for (const auto& p : cloud.xyz)
        points.push_back(w.rig.T_tanker_left_optical * p.cast<double>());
      const auto links = aar_geometry::ComputeLinkPoses(model, aar_sim::BoomJointPositions(pose));
      for (BoomOcclusion* b : {&boom, &thesis}) {
        b->Update(links, w.rig.T_tanker_left_optical.translation(),
                  w.rig.T_tanker_right_optical().translation());
      }
      const std::vector<bool> culled[3] = {boom.Cull(points, CullMethod::kVolumes),
                                           boom.Cull(points, CullMethod::kRaysBvh),
                                           thesis.Cull(points, CullMethod::kVolumes)};
      Counts frame_counts;
      for (size_t i = 0; i < points.size(); ++i) {
        const auto label = static_cast<aar_sim::Label>(frame.left.label.data[cloud.pixel[i]]);
        for (int m = 0; m < 3; ++m) {
          Counts& c = total[m];
          if (label == aar_sim::Label::kBoom) c.boom++, c.boom_culled += culled[m][i];
          if (label == aar_sim::Label::kReceiver) c.receiver++, c.receiver_culled += culled[m][i];
        }
        if (label == aar_sim::Label::kBoom)
          frame_counts.boom++, frame_counts.boom_culled += culled[0][i];
        if (label == aar_sim::Label::kReceiver)
          frame_counts.receiver++, frame_counts.receiver_culled += culled[0][i];
        if (label == aar_sim::Label::kBackground) frame_counts.background += !culled[0][i];
      }
      std::printf(
          "[ frame ] t %.1f s range %.1f m boom pitch %.0f: boom %d/%d culled, receiver "
          "%d/%d culled, %d background points kept\n",
          t, row.position_m.norm(), pose.pitch * 180 / M_PI, frame_counts.boom_culled,
          frame_counts.boom, frame_counts.receiver_culled, frame_counts.receiver,
          frame_counts.background);
    }
  }
  for (int m = 0; m < 3; ++m) {
    const Counts& c = total[m];
    std::printf(
        "[ cull ] %s: %d of %d boom points removed (%.2f%%), %d of %d receiver points "
        "removed (%.2f%%)\n",
        names[m], c.boom_culled, c.boom, 100.0 * c.boom_culled / c.boom, c.receiver_culled,
        c.receiver, 100.0 * c.receiver_culled / c.receiver);
    EXPECT_GT(c.boom, 5000);
    EXPECT_GT(c.receiver, 20000);
    EXPECT_GE(c.boom_culled, 0.99 * c.boom);
    // The thesis's whole ray also takes the receiver seen within the margin's shadow.
    if (m < 2) EXPECT_LE(c.receiver_culled, 0.01 * c.receiver);
  }
}

}  // namespace
}  // namespace aar_occlusion
