#pragma once

#include <string>

#include <aar_geometry/robot_model.h>

namespace aar_testing {

// Where the shipped files are, found through ROS's package index (a sourced workspace), never
// through source paths compiled in. Each throws std::runtime_error when a package is not found.
std::string ModelsDir();            // aar_description's models/
std::string WorkspaceRoot();        // the repository root: the catkin workspace
std::string ConfigDir();            // WorkspaceRoot()/config
std::string DefaultApproachPath();  // config/flight_paths/approach_default.csv

// The boom URDF of aar_description with package:// meshes resolved.
aar_geometry::RobotModel LoadBoomModel();

}  // namespace aar_testing
