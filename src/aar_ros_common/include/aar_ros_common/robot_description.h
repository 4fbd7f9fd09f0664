#pragma once

#include <string>

#include <aar_geometry/robot_model.h>
#include <ros/node_handle.h>

namespace aar_ros_common {

// The boom's URDF from parameter `param` (e.g. "robot_description"), searched up from `nh`'s
// namespace as robot_state_publisher's is found, parsed by aar_geometry::ParseRobotModel with
// package:// meshes found by rospack (ros::package::getPath). Throws std::runtime_error naming
// the parameter when none holds a URDF, aar_geometry::LoadError when the model is refused.
aar_geometry::RobotModel LoadRobotDescription(const ros::NodeHandle& nh, const std::string& param);

}  // namespace aar_ros_common
