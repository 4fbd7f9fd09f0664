#pragma once

#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

namespace aar_ros_common {

// The body of a rostest executable's main: gtest, a ROS node (rostest gives it its name; `name`
// when run alone) and two spinner threads, so that subscribers collect while a test waits.
// Header-only: it is compiled into test executables, never into a node.
inline int RunRostests(int argc, char** argv, const std::string& name) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, name);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}

}  // namespace aar_ros_common
