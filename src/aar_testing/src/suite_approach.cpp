#include "aar_testing/suite_approach.h"

#include <filesystem>

#include <unistd.h>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>
#include <aar_sim/approach.h>
#include <aar_sim/flight_path.h>

#include "aar_testing/paths.h"

namespace aar_testing {

std::string WriteSuiteApproach(int seed, const std::string& receiver) {
  // The contact point as generate_approach takes it: the nozzle tip at the boom's static pose.
  const Eigen::Vector3d tip =
      aar_geometry::ComputeLinkPoses(
          LoadBoomModel(), aar_description::BoomJointPositions(aar_description::DefaultBoomPose()))
          .at("nozzle_tip")
          .translation();
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("aar_approach_" + std::to_string(seed) + "_" + std::to_string(::getpid()) + ".csv"))
          .string();
  aar_sim::ApproachOptions options = aar_sim::VariedApproach(seed);
  if (!receiver.empty())
    options.receptacle = aar_description::LoadReceiverDescription(receiver).receptacle;
  aar_sim::WriteFlightPath(path, aar_sim::GenerateApproach(options, tip));
  return path;
}

}  // namespace aar_testing
