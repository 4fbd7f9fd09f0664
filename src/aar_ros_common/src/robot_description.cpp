#include "aar_ros_common/robot_description.h"

#include <stdexcept>

#include <ros/package.h>

namespace aar_ros_common {

aar_geometry::RobotModel LoadRobotDescription(const ros::NodeHandle& nh, const std::string& param) {
  // The node's namespace first: searchParam finds nothing from the root namespace.
  std::string key = nh.resolveName(param), urdf;
  if (!nh.getParam(key, urdf) && !(nh.searchParam(param, key) && nh.getParam(key, urdf))) {
    throw std::runtime_error("no boom URDF in parameter " + nh.resolveName(param) + " or above it");
  }
  aar_geometry::RobotModelOptions options;
  options.find_package = [](const std::string& package) { return ros::package::getPath(package); };
  return aar_geometry::ParseRobotModel(urdf, key, "", options);
}

}  // namespace aar_ros_common
