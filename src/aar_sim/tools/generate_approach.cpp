// generate_approach: writes the default approach flight path, which ends with the receiver's
// receptacle on the nozzle tip of the boom at its static pose. Deterministic: the committed
// config/flight_paths/approach_default.csv is its output, and a test regenerates it and compares.
// With SEED, one approach of a suite instead (aar_sim::VariedApproach): start offset, closure
// profile, wander and boom motion drawn from SEED; its settings are printed as one CSV line
// (seed,elevation_deg,azimuth_deg,far_speed,mid_speed,near_speed,position_wander_m,
// attitude_wander_deg,boom_swing). With --receiver, the approach of that receiver (a receiver
// description with a receptacle, e.g. MODELS_DIR/rq4.yaml); default: the C-12. With
// --turbulence light|moderate|severe, the path and the boom perturbed by Dryden turbulence
// (aar_sim::Turbulence at its default airspeed and altitude, seeded by --turbulence-seed N,
// default 1; docs/realism/turbulence.md): the CSV then has boom columns.
//   generate_approach [--receiver DESCRIPTION] [--turbulence LEVEL] [--turbulence-seed N]
//                     MODELS_DIR FLIGHT_PATH_CSV [SEED]
#include <filesystem>
#include <iostream>
#include <string>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>

#include "aar_sim/approach.h"
#include "aar_sim/turbulence.h"

namespace {

bool IsWholeNumber(const std::string& s) {
  return !s.empty() && s.size() <= 18 && s.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

int main(int argc, char** argv) {
  std::string receiver;
  aar_sim::TurbulenceOptions turbulence;
  while (argc >= 2 && std::string(argv[1]).rfind("--", 0) == 0) {
    const std::string flag = argv[1];
    if (flag != "--receiver" && flag != "--turbulence" && flag != "--turbulence-seed") {
      std::cerr << "generate_approach: unknown option " << flag << "\n";
      return 2;
    }
    if (argc < 3) {
      std::cerr << "generate_approach: " << flag << " needs a value\n";
      return 2;
    }
    const std::string value = argv[2];
    if (flag == "--receiver") {
      receiver = value;
    } else if (flag == "--turbulence") {
      if (value != "light" && value != "moderate" && value != "severe") {
        std::cerr << "generate_approach: --turbulence must be light, moderate or severe, not '"
                  << value << "'\n";
        return 2;
      }
      turbulence.intensity = aar_sim::ParseTurbulenceIntensity(value);
    } else {
      if (!IsWholeNumber(value)) {
        std::cerr << "generate_approach: --turbulence-seed must be a whole number, not '" << value
                  << "'\n";
        return 2;
      }
      turbulence.seed = std::stoull(value);
    }
    argv[2] = argv[0];
    argc -= 2;
    argv += 2;
  }
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: generate_approach [--receiver DESCRIPTION] [--turbulence LEVEL] "
                 "[--turbulence-seed N] MODELS_DIR FLIGHT_PATH_CSV [SEED]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const std::string csv = argv[2];
  aar_sim::ApproachOptions options;
  if (argc == 4) {
    const std::string seed = argv[3];
    if (!IsWholeNumber(seed)) {
      std::cerr << "generate_approach: SEED must be a whole number, not '" << seed << "'\n";
      return 2;
    }
    options = aar_sim::VariedApproach(std::stoull(seed));
  }
  try {
    if (!receiver.empty()) {
      const auto description = aar_description::LoadReceiverDescription(receiver);
      if (!description.has_receptacle) {
        std::cerr << "generate_approach: " << receiver << ": no receptacle in the description\n";
        return 2;
      }
      options.receptacle = description.receptacle;
    }
    // Kinematics from the boom's URDF (meshes resolved in MODELS_DIR) so that the path and the
    // model cannot disagree.
    const std::string abs_dir = std::filesystem::absolute(dir).string();
    const auto model = aar_geometry::ParseRobotModel(
        aar_description::MakeBoomUrdf(aar_description::BoomModelOptions{}, abs_dir + "/"),
        "boom URDF", abs_dir);
    const auto poses = aar_geometry::ComputeLinkPoses(
        model, aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));
    const Eigen::Vector3d tip = poses.at("nozzle_tip").translation();
    auto rows = aar_sim::GenerateApproach(options, tip);
    if (turbulence.intensity != aar_sim::TurbulenceIntensity::kNone) {
      // The gusts at each row's time; the boom's pitch and roll within the URDF's limits.
      const aar_sim::Turbulence gusts(turbulence, rows.back().t);
      for (aar_sim::FlightPathRow& row : rows) {
        const auto boom = row.boom.value_or(aar_description::DefaultBoomPose());
        auto [perturbed, perturbed_boom] = gusts.Apply(row.t, row, boom, model.joints);
        perturbed.boom = perturbed_boom;
        row = perturbed;
      }
      std::cout << aar_sim::TurbulenceIntensityName(turbulence.intensity) << " turbulence, seed "
                << turbulence.seed << ", sigma " << gusts.sigma() << " m/s\n";
    }
    aar_sim::WriteFlightPath(csv, rows);
    std::cout << "wrote " << csv << " (" << rows.size() << " rows, " << rows.back().t
              << " s, contact range " << rows.back().position_m.norm() << " m)\n";
    if (argc == 4) {
      const auto& o = options;
      std::cout << "approach: " << o.seed << ',' << o.elevation << ',' << o.azimuth << ','
                << o.far_speed << ',' << o.mid_speed << ',' << o.near_speed << ','
                << o.position_wander << ',' << o.attitude_wander << ',' << o.boom_swing << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "generate_approach: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
