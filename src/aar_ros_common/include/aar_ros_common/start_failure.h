#pragma once

#include <exception>
#include <string>

#include <ros/console.h>
#include <ros/init.h>

namespace aar_ros_common {

// A stage whose construction failed (a parameter refused, a model unreadable) ends its process,
// so that a launch requiring it ends within a second, naming the cause, instead of running on
// without it (a nodelet's manager would otherwise stay up, and every frame wait out the
// lockstep timeout). For nodelets: the manager, and so every stage in it, ends.
inline void EndProcessOnStartFailure(const std::string& stage, const std::exception& e) {
  ROS_FATAL_STREAM(stage << ": " << e.what() << " (" << stage
                         << " cannot start: its process ends)");
  ros::requestShutdown();
}

}  // namespace aar_ros_common
