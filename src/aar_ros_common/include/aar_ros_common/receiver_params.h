#pragma once

#include <string>

#include <aar_geometry/receiver_reference.h>

#include "aar_ros_common/param_reader.h"

namespace aar_ros_common {

// The receiver model that the occlusion and registration nodes both sample: ~receiver_mesh
// (default: aar_description's models/receiver.obj), ~sample_density, ~sample_seed and
// ~visibility_tolerance, each over `sampling`'s value. Returns the mesh path.
std::string LoadReceiverModel(ParamReader& params, aar_geometry::ReferenceModelOptions& sampling);

// ~receiver_mesh alone (default: aar_description's models/receiver.obj), for nodes that need the
// model's shape but do not sample it.
std::string LoadReceiverMesh(ParamReader& params);

}  // namespace aar_ros_common
