#include "aar_ros_common/receiver_params.h"

#include <stdexcept>

#include <aar_geometry/load_error.h>
#include <ros/package.h>

namespace aar_ros_common {

std::string DefaultReceiver() {
  return ros::package::getPath("aar_description") + "/models/c12.yaml";
}

aar_description::ReceiverDescription LoadReceiver(ParamReader& params) {
  const std::string path = params.Get<std::string>("receiver", DefaultReceiver());
  try {
    return aar_description::LoadReceiverDescription(path);
  } catch (const aar_geometry::LoadError& e) {
    throw std::invalid_argument("parameter " + params.Resolve("receiver") + ": " + e.what());
  }
}

aar_description::ReceiverDescription LoadReceiverModel(
    ParamReader& params, aar_geometry::ReferenceModelOptions& sampling) {
  aar_description::ReceiverDescription receiver = LoadReceiver(params);
  sampling.points_per_m2 = params.Get("sample_density", sampling.points_per_m2);
  sampling.seed = static_cast<uint64_t>(params.Get("sample_seed", static_cast<int>(sampling.seed)));
  sampling.visibility_tolerance = params.Get("visibility_tolerance", sampling.visibility_tolerance);
  return receiver;
}

aar_geometry::SeedPoints LoadSeedPoints(ParamReader& params) {
  return params.GetChoice<aar_geometry::SeedPoints>(
      "seed_points", "all",
      {{"all", aar_geometry::SeedPoints::kAll},
       {"densest_ball", aar_geometry::SeedPoints::kDensestBall}});
}

}  // namespace aar_ros_common
