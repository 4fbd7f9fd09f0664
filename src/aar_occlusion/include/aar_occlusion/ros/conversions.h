#pragma once

#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "aar_occlusion/boom.h"
#include "aar_occlusion/dynamic_reference.h"

namespace aar_occlusion {

// x, y, z, normal_x, normal_y, normal_z (float32), visibility (uint8: 0 both cameras, 1 left
// only, 2 right only, 3 neither) and rgb (packed as rviz reads it: red, cyan, blue, green by
// class, as the thesis's Fig. 17), unorganized, in the receiver frame.
sensor_msgs::PointCloud2 ToCloud(const DynamicReferenceResult& reference,
                                 const std_msgs::Header& header);

// Per camera (namespaces "left", "right"), one translucent triangle list per boom part in the
// tanker frame: the capped shadow volume reaching `length` [m] past the part.
visualization_msgs::MarkerArray ShadowMarkers(const BoomOcclusion& boom,
                                              const std_msgs::Header& header, double length);

}  // namespace aar_occlusion
