#pragma once

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <ros/console.h>
#include <ros/init.h>
#include <ros/time.h>

namespace aar_ros_common {

// A stage whose construction failed (a parameter refused, a model unreadable) ends its process,
// so that a launch requiring it ends within a second, naming the cause, instead of running on
// without it (a nodelet's manager would otherwise stay up, and every frame wait out the
// lockstep timeout). For nodelets: the manager, and so every stage in it, ends, with status 1.
// At once, after the FATAL line had 0.3 s to reach /rosout: a requested shutdown unloaded the
// manager's nodelets while this one was still loading, and the manager died of SIGSEGV or
// SIGTRAP instead.
inline void EndProcessOnStartFailure(const std::string& stage, const std::exception& e) {
  ROS_FATAL_STREAM(stage << ": " << e.what() << " (" << stage
                         << " cannot start: its process ends)");
  std::fflush(stdout);
  std::fflush(stderr);
  ros::WallDuration(0.3).sleep();
  std::_Exit(1);
}

}  // namespace aar_ros_common
