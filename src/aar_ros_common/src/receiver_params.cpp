#include "aar_ros_common/receiver_params.h"

#include <ros/package.h>

namespace aar_ros_common {

std::string LoadReceiverMesh(ParamReader& params) {
  return params.Get<std::string>("receiver_mesh",
                                 ros::package::getPath("aar_description") + "/models/receiver.obj");
}

std::string LoadReceiverModel(ParamReader& params, aar_geometry::ReferenceModelOptions& sampling) {
  const std::string mesh = LoadReceiverMesh(params);
  sampling.points_per_m2 = params.Get("sample_density", sampling.points_per_m2);
  sampling.seed = static_cast<uint64_t>(params.Get("sample_seed", static_cast<int>(sampling.seed)));
  sampling.visibility_tolerance = params.Get("visibility_tolerance", sampling.visibility_tolerance);
  return mesh;
}

}  // namespace aar_ros_common
