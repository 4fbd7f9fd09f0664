// occlusion_node: boom culling and the dynamic reference model (same code as the nodelet).
#include <ros/ros.h>

#include "aar_occlusion/ros/occlusion_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "occlusion");
  ros::NodeHandle nh, pnh("~");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  std::unique_ptr<aar_occlusion::OcclusionNode> node;
  try {
    node = std::make_unique<aar_occlusion::OcclusionNode>(
        nh, pnh, aar_occlusion::LoadOcclusionNodeOptions(pnh));
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("occlusion: " << e.what());
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
