#pragma once

#include <map>
#include <string>
#include <vector>

#include <aar_alignment/aligner.h>
#include <aar_occlusion/boom.h>
#include <aar_sim/camera.h>
#include <aar_sim/world.h>

namespace aar_testing {

// The rig's cameras as the alignment stage takes them.
aar_alignment::PinholeCamera LeftCamera(const aar_sim::StereoRig& rig);
aar_alignment::PinholeCamera RightCamera(const aar_sim::StereoRig& rig);

// The boom's convex collision parts at a frame (the simulator's link poses), each as its
// vertices in the tanker frame: what the alignment masks out.
std::vector<std::vector<Eigen::Vector3d>> BoomPartsInTanker(
    const std::vector<aar_occlusion::BoomPart>& parts,
    const std::map<std::string, Eigen::Isometry3d>& T_tanker_links);

// The shipped world with config/realism/realistic.yaml's background, sun, propellers and sensor
// (without motion blur and turbulence, which need a path: single frames only).
aar_sim::WorldOptions RealisticWorld();

}  // namespace aar_testing
