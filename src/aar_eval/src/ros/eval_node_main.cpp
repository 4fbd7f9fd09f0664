// eval_node: pairs each pose estimate with the truth at its stamp, publishes /aar/pose_error, and
// writes every frame (estimated or missed) to ~output_dir/frames.csv as it settles.
#include <memory>

#include <ros/ros.h>

#include "aar_eval/ros/eval_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "eval");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<aar_eval::EvalNode> node;
  try {
    node = std::make_unique<aar_eval::EvalNode>(nh, aar_eval::LoadEvalNodeOptions(pnh));
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("eval: " << e.what());
    return 1;
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::waitForShutdown();
  spinner.stop();
  node.reset();  // settles the last frames and writes the summary
  return 0;
}
