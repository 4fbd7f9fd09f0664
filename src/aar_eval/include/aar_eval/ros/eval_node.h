#pragma once

#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <set>

#include <aar_msgs/FrameOutcome.h>
#include <aar_msgs/PoseEstimate.h>
#include <aar_msgs/Visibility.h>
#include <aar_ros_common/error_throttle.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/publisher_check.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "aar_eval/evaluator.h"

namespace aar_eval {

struct EvalNodeOptions {
  std::string output_dir;  // required: frames.csv is written there
  // [s] the simulator's stamp = offset + path time; default: the sim's /sim/stamp_offset, else 1.
  double stamp_offset = 1.0;
  int expected_frames = 0;  // for progress lines "frame k of N"; 0: unknown
  // [s wall] the longest a frame waits for its estimate or a stage's drop before it is settled
  // as a miss (the ledger then says where it was lost).
  double settle_after = 10.0;
  // The node whose aar/pose_estimate is taken (the registration nodelet's manager, or the
  // registration node); estimates from any other publisher are ignored and warned about, and
  // while another node is linked to the topic (checked on the links themselves, whatever caller
  // id it writes) none is taken. Empty: the first publisher heard is taken, and named.
  std::string estimate_publisher;
  // [s] truth is taken only from a sample this close to the frame's stamp: never interpolated
  // across an outage of the truth.
  double truth_tolerance = 0.02;
  std::string truth_frame = "receiver_truth";
  std::string tanker_frame = "tanker";
  // The stereo rigs (issue 44): a further rig R's visibility comes on sim/R/visibility.
  std::vector<std::string> rigs = {"stereo"};
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
EvalNodeOptions LoadEvalNodeOptions(const ros::NodeHandle& private_nh);
EvalNodeOptions LoadEvalNodeOptions(aar_ros_common::ParamReader& params);

// The ROS side of Evaluator: each frame (stereo/left/camera_info) paired with its estimate
// (aar/pose_estimate), the stages' reports (/aar/frame_outcome) and the truth (tf tanker ->
// receiver_truth); each settled frame goes to OUTPUT_DIR/frames.csv and its one outcome to
// OUTPUT_DIR/ledger.csv as it settles, estimated ones to aar/pose_error. On destruction the
// last frames are settled and a summary per region and of the ledger printed. A file that cannot
// be written ends the node (FATAL, naming it).
class EvalNode {
 public:
  EvalNode(ros::NodeHandle nh, const EvalNodeOptions& options);
  ~EvalNode();

 private:
  void OnFrame(const sensor_msgs::CameraInfo::ConstPtr& info);
  void OnEstimate(const ros::MessageEvent<aar_msgs::PoseEstimate const>& event);
  // Whether an estimate from `publisher` is taken (the expected registration's).
  bool FromExpectedPublisher(const std::string& publisher, const ros::Time& stamp);
  // Whether no other node is linked to aar/pose_estimate (else its estimates could carry the
  // expected caller id); warns naming it.
  bool NoStranger(const ros::Time& stamp);
  void OnOutcome(const aar_msgs::FrameOutcome::ConstPtr& outcome);
  // The simulator's /sim/visibility; a malformed one is named and left out.
  void OnVisibility(const aar_msgs::Visibility::ConstPtr& visibility, size_t rig);
  void OnTf(const tf2_msgs::TFMessage::ConstPtr& tf);
  void Settle();                                          // mutex_ held
  void Record(const std::vector<SettledFrame>& settled);  // mutex_ held
  void Write(std::ofstream& out, const std::string& path, const std::string& line);
  std::optional<Eigen::Isometry3d> Truth(int64_t stamp_ns, std::string* error);
  bool TruthReady(int64_t stamp_ns);

  ros::NodeHandle nh_;
  EvalNodeOptions options_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener listener_;
  ros::Publisher error_pub_;
  ros::Subscriber frame_sub_, estimate_sub_, outcome_sub_, visibility_sub_, tf_sub_, tf_static_sub_;
  std::vector<ros::Subscriber> rig_visibility_subs_;  // further rigs'
  ros::WallTimer settle_timer_;
  std::mutex mutex_;
  Evaluator evaluator_;
  std::map<int64_t, std_msgs::Header> estimate_headers_;  // for aar/pose_error
  std::ofstream out_, ledger_out_;
  std::string path_, ledger_path_;
  std::string publisher_;                                // whose estimates are taken
  std::map<std::string, uint64_t> other_publishers_;     // estimates ignored, per caller id
  std::optional<aar_ros_common::PublisherCheck> check_;  // once publisher_ is known
  uint64_t while_strangers_ = 0;  // estimates ignored while another node was linked
  std::mutex truth_mutex_;
  std::set<int64_t> truth_stamps_;  // of the truth samples heard on /tf
  bool truth_static_ = false;       // the truth came on /tf_static
  bool write_failed_ = false;
  std::map<std::string, uint64_t> drops_;  // frames dropped, per "stage (reason)"
  aar_ros_common::ErrorThrottle drop_log_;
  bool stopping_ = false;  // in the destructor: log to stderr, rosconsole is gone
};

}  // namespace aar_eval
