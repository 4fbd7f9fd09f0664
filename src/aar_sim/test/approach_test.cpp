#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_description/receiver_model.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/robot_model.h>
#include <ros/package.h>

#include "aar_sim/approach.h"
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

// The RQ-4 class UAV's default approach: generated for its receptacle, ending with it on the
// nozzle in region C, through every region.
TEST(Rq4Approach, CommittedFileMatchesTheGeneratorAndEndsInItsReceptacle) {
  const std::string committed =
      ros::package::getPath("aar_sim") + "/../../config/flight_paths/approach_rq4.csv";
  const std::string csv =
      std::filesystem::temp_directory_path().string() + "/aar_sim_generated_approach_rq4.csv";
  const std::string command = std::string(AAR_SIM_GENERATE_APPROACH) + " --receiver " + kModels +
                              "/rq4.yaml " + kModels + " " + csv + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(ReadFile(csv), ReadFile(committed))
      << "approach_rq4.csv is stale: run generate_approach --receiver";
  std::filesystem::remove(csv);

  const auto rq4 = aar_description::LoadReceiverDescription(kModels + "/rq4.yaml");
  const FlightPath path = FlightPath::Load(committed);
  const auto poses =
      aar_geometry::ComputeLinkPoses(LoadBoom(), BoomJointPositions(DefaultBoomPose()));
  const Eigen::Vector3d nozzle = poses.at("nozzle_tip").translation();
  const FlightPathRow contact = path.rows().back();
  EXPECT_LT((contact.T_tanker_receiver() * rq4.receptacle - nozzle).norm(), 0.01);
  // The C-12's receptacle would be 0.7 m from the nozzle at the RQ-4's contact pose.
  EXPECT_GT((contact.T_tanker_receiver() * ReceptacleInReceiver() - nozzle).norm(), 0.5);
  // Its description's nominal pose is the contact pose, to the 1 cm it is rounded to.
  EXPECT_LT((rq4.T_tanker_receiver_contact.translation() - contact.position_m).norm(), 0.01);
  const double contact_range = contact.position_m.norm();
  EXPECT_GE(contact_range, 32.0);
  EXPECT_LT(contact_range, 38.0);
  int regions[4] = {0, 0, 0, 0};
  for (const auto& row : path.rows())
    ++regions[static_cast<int>(aar_geometry::RegionOfRange(row.position_m.norm()))];
  EXPECT_EQ(regions[0], 0);
  EXPECT_GT(regions[1], 50);
  EXPECT_GT(regions[2], 50);
  EXPECT_GT(regions[3], 30);
}

// The approaches of a suite: reproducible per seed, different between seeds, each flown from
// 170-175 m through every region to the nozzle in the receptacle, the boom inside its joint
// limits and back at its static pose by contact.
TEST(VariedApproach, ReproducibleDifferentAndEndingInContact) {
  const auto boom = LoadBoom();
  const auto poses = aar_geometry::ComputeLinkPoses(boom, BoomJointPositions(DefaultBoomPose()));
  const Eigen::Vector3d nozzle = poses.at("nozzle_tip").translation();
  std::vector<double> lateral;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const ApproachOptions o = VariedApproach(seed);
    EXPECT_EQ(o.seed, seed);
    const auto rows = GenerateApproach(o, nozzle);
    const auto again = GenerateApproach(VariedApproach(seed), nozzle);
    ASSERT_EQ(rows.size(), again.size());
    EXPECT_EQ(rows[rows.size() / 2].position_m, again[rows.size() / 2].position_m);
    const double start_range = rows.front().position_m.norm();
    EXPECT_GE(start_range, 170.0);
    EXPECT_LE(start_range, 175.0);
    lateral.push_back(rows.front().position_m.y());
    const Eigen::Vector3d receptacle = rows.back().T_tanker_receiver() * o.receptacle;
    EXPECT_LT((receptacle - nozzle).norm(), 0.3);
    int regions[4] = {0, 0, 0, 0};
    for (const auto& row : rows) {
      ++regions[static_cast<int>(aar_geometry::RegionOfRange(row.position_m.norm()))];
      if (o.boom_swing == 0.0) continue;
      ASSERT_TRUE(row.boom.has_value());
      EXPECT_GE(row.boom->pitch, aar_geometry::DegToRad(20.0));
      EXPECT_LE(row.boom->pitch, aar_geometry::DegToRad(40.0));
      EXPECT_LE(std::abs(row.boom->roll), aar_geometry::DegToRad(15.0));
      EXPECT_GE(row.boom->extension, 0.0);
    }
    EXPECT_EQ(regions[0], 0);
    EXPECT_GT(regions[3], 20);
    if (rows.back().boom) {
      EXPECT_NEAR(rows.back().boom->pitch, DefaultBoomPose().pitch, 1e-12);
      EXPECT_NEAR(rows.back().boom->extension, DefaultBoomPose().extension, 1e-12);
    }
  }
  // Start offsets differ between seeds (lateral spread of metres at 175 m).
  const auto [low, high] = std::minmax_element(lateral.begin(), lateral.end());
  EXPECT_GT(*high - *low, 5.0);
  ApproachOptions bad;
  bad.boom_swing = 2.0;
  EXPECT_THROW(GenerateApproach(bad, nozzle), std::invalid_argument);
  bad = {};
  bad.azimuth = 90.0;
  EXPECT_THROW(GenerateApproach(bad, nozzle), std::invalid_argument);
}

}  // namespace
}  // namespace aar_sim
