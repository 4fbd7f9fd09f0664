// registration_node: the receiver's pose from each sensed cloud (same code as the nodelet).
#include <ros/ros.h>

#include "aar_registration/ros/registration_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "registration");
  ros::NodeHandle nh, pnh("~");
  ros::AsyncSpinner spinner(1);
  spinner.start();  // tf arrives while the reference model is built
  std::unique_ptr<aar_registration::RegistrationNode> node;
  try {
    node = std::make_unique<aar_registration::RegistrationNode>(
        nh, pnh, aar_registration::LoadRegistrationNodeOptions(pnh));
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("registration: " << e.what());
    return 1;
  }
  ros::waitForShutdown();
  // Join the callback threads before the node goes: a frame still in flight at shutdown used the
  // node's members after they were destroyed (ASan, heap-use-after-free, in scripts/test
  // --sanitize); the spinner, made first, would otherwise stop only after the node is gone.
  spinner.stop();
  node.reset();
  return 0;
}
