#pragma once

#include <aar_alignment/aligner.h>
#include <aar_sim/camera.h>
#include <aar_sim/world.h>

namespace aar_testing {

// The rig's cameras as the alignment stage takes them.
aar_alignment::PinholeCamera LeftCamera(const aar_sim::StereoRig& rig);
aar_alignment::PinholeCamera RightCamera(const aar_sim::StereoRig& rig);

// The shipped world with config/realism/realistic.yaml's background, sun, propellers and sensor
// (without motion blur and turbulence, which need a path: single frames only).
aar_sim::WorldOptions RealisticWorld();

}  // namespace aar_testing
