// generate_approach: writes the default approach flight path, which ends with the receiver's
// receptacle on the nozzle tip of the boom at its static pose. Deterministic: the committed
// config/flight_paths/approach_default.csv is its output, and a test regenerates it and compares.
//   generate_approach MODELS_DIR FLIGHT_PATH_CSV
#include <filesystem>
#include <iostream>
#include <string>

#include <aar_description/boom_model.h>
#include <aar_geometry/robot_model.h>

#include "aar_sim/approach.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: generate_approach MODELS_DIR FLIGHT_PATH_CSV\n";
    return 2;
  }
  const std::string dir = argv[1];
  const std::string csv = argv[2];
  try {
    // Kinematics from the boom's URDF (meshes resolved in MODELS_DIR) so that the path and the
    // model cannot disagree.
    const std::string abs_dir = std::filesystem::absolute(dir).string();
    const auto model = aar_geometry::ParseRobotModel(
        aar_description::MakeBoomUrdf(aar_description::BoomModelOptions{}, abs_dir + "/"),
        "boom URDF", abs_dir);
    const auto poses = aar_geometry::ComputeLinkPoses(
        model, aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));
    const Eigen::Vector3d tip = poses.at("nozzle_tip").translation();
    const auto rows = aar_sim::GenerateApproach(aar_sim::ApproachOptions{}, tip);
    aar_sim::WriteFlightPath(csv, rows);
    std::cout << "wrote " << csv << " (" << rows.size() << " rows, " << rows.back().t
              << " s, contact range " << rows.back().position_m.norm() << " m)\n";
  } catch (const std::exception& e) {
    std::cerr << "generate_approach: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
