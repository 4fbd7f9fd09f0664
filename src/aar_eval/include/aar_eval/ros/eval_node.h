#pragma once

#include <fstream>
#include <map>
#include <mutex>
#include <string>

#include <aar_msgs/PoseEstimate.h>
#include <aar_ros_common/param_reader.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "aar_eval/evaluator.h"

namespace aar_eval {

struct EvalNodeOptions {
  std::string output_dir;  // required: frames.csv is written there
  // [s] the simulator's stamp = offset + path time; default: the sim's /sim/stamp_offset, else 1.
  double stamp_offset = 1.0;
  int expected_frames = 0;  // for progress lines "frame k of N"; 0: unknown
  int grace_frames = 2;     // newer frames announced before a frame without estimate is a miss
  std::string truth_frame = "receiver_truth";
  std::string tanker_frame = "tanker";
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
EvalNodeOptions LoadEvalNodeOptions(const ros::NodeHandle& private_nh);
EvalNodeOptions LoadEvalNodeOptions(aar_ros_common::ParamReader& params);

// The ROS side of Evaluator: each frame (stereo/left/camera_info) paired with its estimate
// (aar/pose_estimate) and the truth (tf tanker -> receiver_truth); each settled frame goes to
// OUTPUT_DIR/frames.csv as it settles, estimated ones to aar/pose_error. On destruction the last
// frames are settled and a summary per region printed.
class EvalNode {
 public:
  EvalNode(ros::NodeHandle nh, const EvalNodeOptions& options);
  ~EvalNode();

 private:
  void OnFrame(const sensor_msgs::CameraInfo::ConstPtr& info);
  void OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& estimate);
  void Record(const std::vector<SettledFrame>& settled);  // mutex_ held
  std::optional<Eigen::Isometry3d> Truth(int64_t stamp_ns, std::string* error) const;

  ros::NodeHandle nh_;
  EvalNodeOptions options_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener listener_;
  ros::Publisher error_pub_;
  ros::Subscriber frame_sub_, estimate_sub_;
  std::mutex mutex_;
  Evaluator evaluator_;
  std::map<int64_t, std_msgs::Header> estimate_headers_;  // for aar/pose_error
  std::ofstream out_;
  std::string path_;
  bool stopping_ = false;  // in the destructor: log to stderr, rosconsole is gone
};

}  // namespace aar_eval
