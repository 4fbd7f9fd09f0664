#include <gtest/gtest.h>

#include <filesystem>

#include <aar_description/boom_model.h>
#include <aar_geometry/adjacency.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/surface_sampling.h>
#include <aar_geometry/weld.h>
#include <ros/package.h>

#include "aar_occlusion/boom.h"

namespace aar_occlusion {
namespace {

// Receiver samples at a pose, classified by the boom parts' shadow volumes from both cameras,
// agree with an independent Embree ray cast against the same parts, on points farther than 1 cm
// from every shadow boundary.
void CheckAgainstRayCast(const aar_description::BoomPose& boom_pose,
                         const Eigen::Isometry3d& T_tanker_receiver, double min_hidden_fraction) {
  const std::string models = ros::package::getPath("aar_description") + "/models";
  aar_geometry::RobotModelOptions urdf;
  urdf.package_paths = {models + "/../.."};
  const auto model = aar_geometry::LoadRobotModel(models + "/boom.urdf", urdf);
  const auto poses =
      aar_geometry::ComputeLinkPoses(model, aar_description::BoomJointPositions(boom_pose));
  const aar_geometry::TriangleMesh collision =
      aar_geometry::RobotMesh(model, poses, aar_geometry::GeometryKind::kCollision);
  // The default rig: centre (-20, 1, -3) m looking aft, 0.5 m baseline (config/sim.yaml).
  const Eigen::Vector3d eyes[2] = {{-20.0, 0.75, -3.0}, {-20.0, 1.25, -3.0}};

  BoomOcclusion boom(LoadBoomParts(model));
  boom.Update(poses, eyes[0], eyes[1]);

  const auto receiver = aar_geometry::LoadMesh(models + "/receiver.obj");
  aar_geometry::SurfaceSamplingOptions sampling;
  sampling.num_points = 24000;
  sampling.seed = 5;
  const auto samples = aar_geometry::SampleSurface(receiver, sampling);
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : samples.points) points.push_back(T_tanker_receiver * p);
  const std::vector<Visibility> by_volumes = boom.Classify(points);

  // Oracle: a ray from each eye to the point, against the boom parts only (the receiver's own
  // self-occlusion is not the boom's).
  const aar_geometry::VisibilityTester rays(collision);
  std::vector<Eigen::Vector3d> no_normal(points.size(), Eigen::Vector3d::Zero());
  int compared = 0, agree = 0, hidden = 0;
  std::vector<bool> seen[2];
  for (int e = 0; e < 2; ++e) {
    std::vector<Eigen::Vector3d> towards(points.size());
    for (size_t i = 0; i < points.size(); ++i)
      towards[i] = (eyes[e] - points[i]).normalized();  // "faces" the eye
    seen[e] = rays.Visible(points, towards, eyes[e], 0.0);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    // Skip points within 1 cm of any shadow boundary plane that is active there.
    bool near_boundary = false;
    for (int e = 0; e < 2 && !near_boundary; ++e) {
      for (const auto& s : boom.shadows(e)) {
        if (s.Contains(points[i], 0.01) && !s.Contains(points[i], -0.01)) near_boundary = true;
      }
    }
    if (near_boundary) continue;
    const Visibility oracle = seen[0][i] && seen[1][i] ? Visibility::kBoth
                              : seen[0][i]             ? Visibility::kLeftOnly
                              : seen[1][i]             ? Visibility::kRightOnly
                                                       : Visibility::kNeither;
    ++compared;
    agree += oracle == by_volumes[i];
    hidden += by_volumes[i] != Visibility::kBoth;
  }
  std::printf(
      "[ oracle ] boom pitch %.0f deg roll %.0f deg ext %.1f m, receiver at %.1f m: %d of %d "
      "points agree "
      "(%.3f%%), %d hidden from at least one camera\n",
      boom_pose.pitch * 180 / M_PI, boom_pose.roll * 180 / M_PI, boom_pose.extension,
      T_tanker_receiver.translation().norm(), agree, compared, 100.0 * agree / compared, hidden);
  EXPECT_GE(compared, 20000);
  EXPECT_GE(agree + 2, compared);  // measured: 100.000 % in all four cases
  EXPECT_GE(static_cast<double>(hidden) / compared,
            min_hidden_fraction);  // the boom really occludes
}

Eigen::Isometry3d Row(double x, double y, double z) {
  return aar_geometry::MakeTransform({x, y, z}, {0.0, -2.0 * M_PI / 180.0, 0.0});
}

TEST(Oracle, ShadowVolumesAgreeWithRayCasting) {
  CheckAgainstRayCast(aar_description::DefaultBoomPose(), Row(-90.0, 0.5, -24.0),
                      0.001);  // region A
  CheckAgainstRayCast(aar_description::DefaultBoomPose(), Row(-35.0, 0.0, -10.19),
                      0.05);  // contact
  CheckAgainstRayCast(aar_description::DefaultBoomPose(), Row(-50.0, 0.5, -14.0),
                      0.01);  // region B
  aar_description::BoomPose swung{36.0 * M_PI / 180.0, -8.0 * M_PI / 180.0, 3.0};
  CheckAgainstRayCast(swung, Row(-38.0, -1.0, -12.0), 0.01);
}

}  // namespace
}  // namespace aar_occlusion
