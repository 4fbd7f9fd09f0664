#include "aar_testing/paths.h"

#include <stdexcept>

#include <ros/package.h>

namespace aar_testing {
namespace {

std::string PackagePath(const std::string& name) {
  const std::string path = ros::package::getPath(name);
  if (path.empty()) {
    throw std::runtime_error("package " + name +
                             " not found: source the workspace's devel/setup.bash first");
  }
  return path;
}

}  // namespace

std::string ModelsDir() { return PackagePath("aar_description") + "/models"; }

std::string WorkspaceRoot() { return PackagePath("aar_testing") + "/../.."; }

std::string ConfigDir() { return WorkspaceRoot() + "/config"; }

std::string DefaultApproachPath() { return ConfigDir() + "/flight_paths/approach_default.csv"; }

aar_geometry::RobotModel LoadBoomModel() {
  aar_geometry::RobotModelOptions options;
  options.package_paths = {ModelsDir() + "/../.."};
  return aar_geometry::LoadRobotModel(ModelsDir() + "/boom.urdf", options);
}

}  // namespace aar_testing
