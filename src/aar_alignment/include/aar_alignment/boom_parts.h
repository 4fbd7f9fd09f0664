#pragma once

#include <map>
#include <string>
#include <vector>

#include <aar_description/boom_parts.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_alignment/outline.h"

namespace aar_alignment {

// The boom's convex collision parts (aar_description::LoadBoomCollisionParts) placed at a frame's
// link poses, each as its vertices in the tanker frame: what the alignment masks out of the images.
// A part whose link has no pose is left out.
std::vector<std::vector<Eigen::Vector3d>> BoomPartsInTanker(
    const std::vector<aar_description::BoomCollisionPart>& parts,
    const std::map<std::string, Eigen::Isometry3d>& T_tanker_links);

// The parts (BoomPartsInTanker) projected into `camera`, each grown by `margin_px`: CV_8U of the
// camera's size, 1 where the boom lies. A part that reaches behind the camera's plane is clipped
// to it first. Empty when there are no parts.
cv::Mat BoomMask(const PinholeCamera& camera,
                 const std::vector<std::vector<Eigen::Vector3d>>& parts, double margin_px);

}  // namespace aar_alignment
