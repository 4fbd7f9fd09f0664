#include "aar_eval/ros/eval_node.h"

#include <filesystem>
#include <iostream>
#include <sstream>

#include <aar_msgs/PoseError.h>
#include <aar_ros_common/tf_bridge.h>

#include "aar_eval/ros/conversions.h"

namespace aar_eval {

EvalNode::EvalNode(ros::NodeHandle nh, const EvalNodeOptions& options)
    : nh_(nh),
      options_(options),
      tf_(ros::Duration(120.0)),
      listener_(tf_),
      evaluator_(options.stamp_offset, options.expected_frames, options.grace_frames) {
  std::filesystem::create_directories(options_.output_dir);
  path_ = options_.output_dir + "/frames.csv";
  out_.open(path_);
  if (!out_) throw std::runtime_error(path_ + ": cannot be written");
  out_ << FrameCsvHeader() << "\n" << std::flush;
  error_pub_ = nh_.advertise<aar_msgs::PoseError>("aar/pose_error", 10);
  // Long queues: a frame dropped here would have neither a row nor a log line (small messages).
  frame_sub_ = nh_.subscribe("stereo/left/camera_info", 100, &EvalNode::OnFrame, this);
  estimate_sub_ = nh_.subscribe("aar/pose_estimate", 100, &EvalNode::OnEstimate, this);
}

EvalNode::~EvalNode() {
  frame_sub_.shutdown();
  estimate_sub_.shutdown();
  std::lock_guard<std::mutex> lock(mutex_);
  stopping_ = true;
  // The run is over: what has no estimate now is a miss.
  Record(evaluator_.SettleAll(
      [this](int64_t stamp_ns, std::string* error) { return Truth(stamp_ns, error); }));
  // stdout, not rosconsole: it drops messages once ROS has shut down.
  for (const auto& [region, s] : ComputeRegionStats(evaluator_.records())) {
    std::cout << "eval: region " << region << ": " << s.estimated << " of " << s.frames
              << " frames estimated; mean |x| " << s.mean_abs[0] << " m, |yaw| " << s.mean_abs[5]
              << " deg\n";
  }
  if (evaluator_.estimates_without_frame() > 0) {
    std::cout << "eval: " << evaluator_.estimates_without_frame()
              << " estimates for frames never announced were left out\n";
  }
  if (evaluator_.frames_without_truth() > 0) {
    std::cout << "eval: " << evaluator_.frames_without_truth()
              << " frames had no truth and were left out\n";
  }
  std::cout << "eval: wrote " << evaluator_.records().size() << " frames to " << path_ << std::endl;
}

std::optional<Eigen::Isometry3d> EvalNode::Truth(int64_t stamp_ns, std::string* error) const {
  // No wait: a frame settles after later frames came, and their truth with them.
  return aar_ros_common::LookupTransform(tf_, options_.tanker_frame, options_.truth_frame,
                                         ToRosTime(stamp_ns), 0.0, "the frame's stamp", error);
}

void EvalNode::OnFrame(const sensor_msgs::CameraInfo::ConstPtr& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int64_t newest = evaluator_.newest_frame_ns();
  switch (evaluator_.AddFrame(ToNs(info->header.stamp))) {
    case Evaluator::FrameStatus::kOlder:
      ROS_WARN_STREAM("eval: frame " << info->header.stamp << " is older than the last one ("
                                     << ToRosTime(newest) << "): ignored; did the clock jump?");
      return;
    case Evaluator::FrameStatus::kRepeat:
      return;  // the same frame again
    case Evaluator::FrameStatus::kNew:
      break;
  }
  Record(evaluator_.SettleReady(
      [this](int64_t stamp_ns, std::string* error) { return Truth(stamp_ns, error); }));
}

void EvalNode::OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& estimate) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int64_t stamp = ToNs(estimate->header.stamp);
  if (!evaluator_.AddEstimate(stamp, ToEstimate(*estimate))) {
    ROS_WARN_STREAM("eval: estimate for " << estimate->header.stamp
                                          << " came after its frame was settled: ignored");
    return;
  }
  estimate_headers_[stamp] = estimate->header;
}

void EvalNode::Record(const std::vector<SettledFrame>& settled) {
  for (const SettledFrame& s : settled) {
    const auto header = estimate_headers_.find(s.stamp_ns);
    std_msgs::Header estimate_header;
    if (header != estimate_headers_.end()) {
      estimate_header = header->second;
      estimate_headers_.erase(header);
    }
    if (!s.no_truth.empty()) {
      std::ostringstream line;
      line << "eval: no truth for frame " << ToRosTime(s.stamp_ns) << " (" << s.no_truth
           << "); frame left out";
      // The last frames settle as the node stops, when rosconsole drops what it is given.
      if (stopping_)
        std::cerr << line.str() << std::endl;
      else
        ROS_ERROR_STREAM(line.str());
      continue;
    }
    const FrameRecord& f = s.record;
    if (f.estimated) error_pub_.publish(ToPoseErrorMsg(f, estimate_header));
    out_ << FrameCsvRow(f) << "\n" << std::flush;
    if (!s.progress.empty()) ROS_INFO_STREAM(s.progress);
  }
}

}  // namespace aar_eval
