#pragma once

#include <vector>

#include <aar_msgs/PoseEstimate.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <Eigen/Core>

#include "aar_registration/registrar.h"

namespace aar_registration {

// A frame's reference from aar/reference_cloud (receiver frame): the points both cameras see
// (visibility class 0) when the cloud has classes, else all; normals when it has them.
struct ReferencePoints {
  std::vector<Eigen::Vector3d> points;   // [m]
  std::vector<Eigen::Vector3d> normals;  // unit, or empty
};
// Throws std::invalid_argument for a cloud that cannot be read.
ReferencePoints ToReferencePoints(const sensor_msgs::PointCloud2& msg);

// More than one rig (issue 44): the union of the rigs' references, in rig order. The rigs sample
// one mesh alike, so a sample two rigs see is one point in both: a later rig's point equal to
// one already in is left out (its normal with it). The first rig's whole, as it came.
ReferencePoints MergeReferences(std::vector<ReferencePoints> rigs);

// The estimate message of a registration (valid or not); `total_ms` [ms] from the cloud's
// arrival. The header names the tanker frame and the cloud's stamp.
aar_msgs::PoseEstimate ToPoseEstimate(const RegistrarResult& result, const std_msgs::Header& header,
                                      double total_ms);

}  // namespace aar_registration
