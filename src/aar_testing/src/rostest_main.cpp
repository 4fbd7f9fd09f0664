// The main of every rostest executable: gtest, a ROS node (rostest gives it its name) and two
// spinner threads, so that subscribers collect while a test waits.
#include <gtest/gtest.h>

#include <ros/ros.h>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "aar_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
