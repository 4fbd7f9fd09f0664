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
#include <stdexcept>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>

#include "aar_sim/approach.h"
#include "aar_sim/turbulence.h"

namespace {

// A bad command line or receiver: the message is printed as it is and the exit status is 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

bool IsWholeNumber(const std::string& s) {
  return !s.empty() && s.size() <= 18 && s.find_first_not_of("0123456789") == std::string::npos;
}

struct Arguments {
  std::string receiver;  // a receiver description; empty: the C-12
  aar_sim::TurbulenceOptions turbulence;
  std::string dir;      // MODELS_DIR
  std::string csv;      // FLIGHT_PATH_CSV
  bool varied = false;  // with SEED: options are VariedApproach(SEED)
  aar_sim::ApproachOptions options;
};

// --receiver, --turbulence or --turbulence-seed with its value.
void ParseOption(const std::string& flag, const std::string& value, Arguments* args) {
  if (flag == "--receiver") {
    args->receiver = value;
  } else if (flag == "--turbulence") {
    if (value != "light" && value != "moderate" && value != "severe") {
      throw UsageError("generate_approach: --turbulence must be light, moderate or severe, not '" +
                       value + "'");
    }
    args->turbulence.intensity = aar_sim::ParseTurbulenceIntensity(value);
  } else {
    if (!IsWholeNumber(value)) {
      throw UsageError("generate_approach: --turbulence-seed must be a whole number, not '" +
                       value + "'");
    }
    args->turbulence.seed = std::stoull(value);
  }
}

Arguments ParseArguments(int argc, char** argv) {
  Arguments args;
  int i = 1;
  for (; i < argc && std::string(argv[i]).rfind("--", 0) == 0; i += 2) {
    const std::string flag = argv[i];
    if (flag != "--receiver" && flag != "--turbulence" && flag != "--turbulence-seed") {
      throw UsageError("generate_approach: unknown option " + flag);
    }
    if (i + 1 >= argc) throw UsageError("generate_approach: " + flag + " needs a value");
    ParseOption(flag, argv[i + 1], &args);
  }
  const int positional = argc - i;
  if (positional != 2 && positional != 3) {
    throw UsageError(
        "usage: generate_approach [--receiver DESCRIPTION] [--turbulence LEVEL] "
        "[--turbulence-seed N] MODELS_DIR FLIGHT_PATH_CSV [SEED]");
  }
  args.dir = argv[i];
  args.csv = argv[i + 1];
  if (positional == 3) {
    const std::string seed = argv[i + 2];
    if (!IsWholeNumber(seed)) {
      throw UsageError("generate_approach: SEED must be a whole number, not '" + seed + "'");
    }
    args.varied = true;
    args.options = aar_sim::VariedApproach(std::stoull(seed));
  }
  return args;
}

// The receptacle of the receiver description at `path`.
Eigen::Vector3d ReceptacleOf(const std::string& path) {
  const auto description = aar_description::LoadReceiverDescription(path);
  if (!description.has_receptacle) {
    throw UsageError("generate_approach: " + path + ": no receptacle in the description");
  }
  return description.receptacle;
}

// The boom's kinematics from its URDF (meshes resolved in MODELS_DIR) so that the path and the
// model cannot disagree.
aar_geometry::RobotModel BoomModel(const std::string& dir) {
  const std::string abs_dir = std::filesystem::absolute(dir).string();
  return aar_geometry::ParseRobotModel(
      aar_description::MakeBoomUrdf(aar_description::BoomModelOptions{}, abs_dir + "/"),
      "boom URDF", abs_dir);
}

// The gusts at each row's time; the boom's pitch and roll within the URDF's limits.
void ApplyTurbulence(const aar_sim::TurbulenceOptions& turbulence,
                     const aar_geometry::RobotModel& model,
                     std::vector<aar_sim::FlightPathRow>* rows) {
  const aar_sim::Turbulence gusts(turbulence, rows->back().t);
  for (aar_sim::FlightPathRow& row : *rows) {
    const auto boom = row.boom.value_or(aar_description::DefaultBoomPose());
    auto [perturbed, perturbed_boom] = gusts.Apply(row.t, row, boom, model.joints);
    perturbed.boom = perturbed_boom;
    row = perturbed;
  }
  std::cout << aar_sim::TurbulenceIntensityName(turbulence.intensity) << " turbulence, seed "
            << turbulence.seed << ", sigma " << gusts.sigma() << " m/s\n";
}

// A varied approach's settings as one CSV line.
void PrintApproach(const aar_sim::ApproachOptions& o) {
  std::cout << "approach: " << o.seed << ',' << o.elevation << ',' << o.azimuth << ','
            << o.far_speed << ',' << o.mid_speed << ',' << o.near_speed << ',' << o.position_wander
            << ',' << o.attitude_wander << ',' << o.boom_swing << "\n";
}

void Generate(Arguments args) {
  if (!args.receiver.empty()) args.options.receptacle = ReceptacleOf(args.receiver);
  const aar_geometry::RobotModel model = BoomModel(args.dir);
  const auto poses = aar_geometry::ComputeLinkPoses(
      model, aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));
  const Eigen::Vector3d tip = poses.at("nozzle_tip").translation();
  auto rows = aar_sim::GenerateApproach(args.options, tip);
  if (args.turbulence.intensity != aar_sim::TurbulenceIntensity::kNone) {
    ApplyTurbulence(args.turbulence, model, &rows);
  }
  aar_sim::WriteFlightPath(args.csv, rows);
  std::cout << "wrote " << args.csv << " (" << rows.size() << " rows, " << rows.back().t
            << " s, contact range " << rows.back().position_m.norm() << " m)\n";
  if (args.varied) PrintApproach(args.options);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    Generate(ParseArguments(argc, argv));
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "generate_approach: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
