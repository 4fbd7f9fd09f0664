// stereo_node: aar_stereo as a standalone process (the same code as aar_stereo/StereoNodelet).
#include <ros/ros.h>

#include "aar_stereo/ros/stereo_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "stereo");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<aar_stereo::StereoNode> node;
  try {
    node =
        std::make_unique<aar_stereo::StereoNode>(nh, pnh, aar_stereo::LoadStereoNodeOptions(pnh));
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("stereo: " << e.what());
    return 1;
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
