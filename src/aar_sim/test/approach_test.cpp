#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_model.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/robot_model.h>
#include <ros/package.h>

#include "aar_sim/flight_path.h"

namespace aar_sim {
namespace {

using aar_description::BoomJointPositions;
using aar_description::DefaultBoomPose;
using aar_description::ReceptacleInReceiver;
const std::string kModels = ros::package::getPath("aar_description") + "/models";
// The shipped approach, in the workspace's config/ (the repository root is the workspace).
const std::string kApproach =
    ros::package::getPath("aar_sim") + "/../../config/flight_paths/approach_default.csv";

aar_geometry::RobotModel LoadBoom() {
  aar_geometry::RobotModelOptions options;
  options.package_paths = {std::filesystem::path(kModels).parent_path().parent_path().string()};
  return aar_geometry::LoadRobotModel(kModels + "/boom.urdf", options);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(DefaultApproach, CommittedFileMatchesTheGenerator) {
  const std::string csv =
      std::filesystem::temp_directory_path().string() + "/aar_sim_generated_approach.csv";
  const std::string command =
      std::string(AAR_SIM_GENERATE_APPROACH) + " " + kModels + " " + csv + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(ReadFile(csv), ReadFile(kApproach))
      << "approach_default.csv is stale: run generate_approach";
  std::filesystem::remove(csv);
}

TEST(DefaultApproach, EndsWithTheNozzleInTheReceptacle) {
  const FlightPath path = FlightPath::Load(kApproach);
  const auto boom = LoadBoom();
  EXPECT_FALSE(path.has_boom());  // the boom holds DefaultBoomPose
  const auto poses = aar_geometry::ComputeLinkPoses(boom, BoomJointPositions(DefaultBoomPose()));
  const Eigen::Vector3d nozzle = poses.at("nozzle_tip").translation();
  const FlightPathRow contact = path.rows().back();
  const Eigen::Vector3d receptacle = contact.T_tanker_receiver() * ReceptacleInReceiver();
  EXPECT_LT((receptacle - nozzle).norm(), 0.3)
      << "receptacle " << receptacle.transpose() << ", nozzle " << nozzle.transpose();
  const double contact_range = contact.position_m.norm();
  EXPECT_GE(contact_range, 32.0);
  EXPECT_LE(contact_range, 37.0);
  const double start_range = path.rows().front().position_m.norm();
  EXPECT_GE(start_range, 170.0);
  EXPECT_LE(start_range, 175.0);
}

TEST(DefaultApproach, ClosesFastFarOutAndSlowlyNear) {
  const FlightPath path = FlightPath::Load(kApproach);
  const auto& rows = path.rows();
  double max_near = 0.0, max_far = 0.0;
  int regions[4] = {0, 0, 0, 0};
  for (size_t i = 1; i < rows.size(); ++i) {
    const double range = rows[i].position_m.norm();
    const double start = rows[i - 1].position_m.norm();  // the step's speed is set at its start
    const double closure = (start - range) / (rows[i].t - rows[i - 1].t);
    double& max = start < 50.0 ? max_near : max_far;
    max = std::max(max, closure);
    ++regions[static_cast<int>(aar_geometry::RegionOfRange(range))];
  }
  EXPECT_LT(max_near, 1.0);  // [m/s]
  EXPECT_GT(max_far, 4.0);
  EXPECT_EQ(regions[0], 0);  // every row in region A, B or C
  EXPECT_GT(regions[1], 50);
  EXPECT_GT(regions[2], 50);
  EXPECT_GT(regions[3], 30);
}

}  // namespace
}  // namespace aar_sim
