#pragma once

#include <string>

#include <aar_description/receiver_description.h>
#include <aar_geometry/receiver_reference.h>

#include "aar_ros_common/param_reader.h"

namespace aar_ros_common {

// The receiver that the occlusion and registration nodes both sample: ~receiver (a receiver
// description, aar_description/receiver_description.h, or a bare mesh; default: aar_description's
// models/c12.yaml), ~sample_density, ~sample_seed and ~visibility_tolerance, each over
// `sampling`'s value. Throws std::invalid_argument naming ~receiver and the file's problem.
aar_description::ReceiverDescription LoadReceiverModel(
    ParamReader& params, aar_geometry::ReferenceModelOptions& sampling);

// ~receiver alone, for nodes that need the model's shape but do not sample it.
aar_description::ReceiverDescription LoadReceiver(ParamReader& params);

// ~seed_points: all (default) or densest_ball (aar_geometry::SeedPoints), occlusion's and
// registration's centroid seed.
aar_geometry::SeedPoints LoadSeedPoints(ParamReader& params);

// The default receiver: aar_description's models/c12.yaml.
std::string DefaultReceiver();

}  // namespace aar_ros_common
