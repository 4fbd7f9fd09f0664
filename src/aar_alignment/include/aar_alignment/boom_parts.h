#pragma once

#include <map>
#include <string>
#include <vector>

#include <aar_occlusion/boom.h>
#include <Eigen/Geometry>

namespace aar_alignment {

// The boom's convex collision parts (aar_occlusion::LoadBoomParts) placed at a frame's link poses,
// each as its vertices in the tanker frame: what the alignment masks out of the images. A part
// whose link has no pose is left out.
std::vector<std::vector<Eigen::Vector3d>> BoomPartsInTanker(
    const std::vector<aar_occlusion::BoomPart>& parts,
    const std::map<std::string, Eigen::Isometry3d>& T_tanker_links);

}  // namespace aar_alignment
