// eval_node: pairs each pose estimate with the truth at its stamp, publishes /aar/pose_error, and
// writes every frame (estimated or missed) to ~output_dir/frames.csv as it settles.
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_listener.h>

#include "aar_eval/tables.h"

namespace {

using aar_eval::FrameRecord;

class EvalNode {
 public:
  EvalNode(ros::NodeHandle nh, ros::NodeHandle pnh)
      : nh_(nh), tf_(ros::Duration(120.0)), listener_(tf_) {
    std::string output_dir;
    if (!pnh.getParam("output_dir", output_dir) || output_dir.empty()) {
      throw std::invalid_argument("required parameter " + pnh.resolveName("output_dir") +
                                  " is not set");
    }
    // The simulator's stamp offset (stamp = offset + path time), read where it is configured.
    if (!pnh.getParam("stamp_offset", stamp_offset_))
      nh.param("/sim/stamp_offset", stamp_offset_, 1.0);
    pnh.param("expected_frames", expected_frames_, 0);
    pnh.param<std::string>("truth_frame", truth_frame_, "receiver_truth");
    pnh.param<std::string>("tanker_frame", tanker_frame_, "tanker");
    std::filesystem::create_directories(output_dir);
    path_ = output_dir + "/frames.csv";
    out_.open(path_);
    if (!out_) throw std::runtime_error(path_ + ": cannot be written");
    out_ << aar_eval::FrameCsvHeader() << "\n" << std::flush;
    error_pub_ = nh_.advertise<aar_msgs::PoseError>("aar/pose_error", 10);
    frame_sub_ = nh_.subscribe("stereo/left/camera_info", 10, &EvalNode::OnFrame, this);
    estimate_sub_ = nh_.subscribe("aar/pose_estimate", 10, &EvalNode::OnEstimate, this);
  }

  ~EvalNode() {
    frame_sub_.shutdown();
    estimate_sub_.shutdown();
    std::lock_guard<std::mutex> lock(mutex_);
    Settle(ros::TIME_MAX);  // the run is over: what has no estimate now is a miss
    // stdout, not rosconsole: it drops messages once ROS has shut down.
    const auto stats = aar_eval::ComputeRegionStats(records_);
    for (const auto& [region, s] : stats) {
      std::cout << "eval: region " << region << ": " << s.estimated << " of " << s.frames
                << " frames estimated; mean |x| " << s.mean_abs[0] << " m, |yaw| " << s.mean_abs[5]
                << " deg\n";
    }
    if (!estimates_.empty()) {
      std::cout << "eval: " << estimates_.size()
                << " estimates for frames never announced were left out\n";
    }
    if (no_truth_ > 0)
      std::cout << "eval: " << no_truth_ << " frames had no truth and were left out\n";
    std::cout << "eval: wrote " << records_.size() << " frames to " << path_ << std::endl;
  }

 private:
  void OnFrame(const sensor_msgs::CameraInfo::ConstPtr& info) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!frames_.empty() && info->header.stamp <= frames_.back()) {
      if (info->header.stamp < frames_.back()) {
        ROS_WARN_STREAM("eval: frame " << info->header.stamp << " is older than the last one ("
                                       << frames_.back() << "): ignored; did the clock jump?");
      }
      return;  // the same frame again
    }
    frames_.push_back(info->header.stamp);
    // The frame before the previous one is settled: lockstep publishes a frame only after the
    // estimate of the one before (or a timeout); one frame of grace covers message ordering.
    if (frames_.size() >= 3) Settle(frames_[frames_.size() - 2]);
  }

  void OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& estimate) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (settled_.count(estimate->header.stamp)) {
      ROS_WARN_STREAM("eval: estimate for " << estimate->header.stamp
                                            << " came after its frame was settled: ignored");
      return;
    }
    estimates_[estimate->header.stamp] = estimate;
  }

  // Records every frame older than `before`, estimated or missed, in stamp order.
  void Settle(const ros::Time& before) {
    while (!frames_.empty() && frames_.front() < before) {
      const ros::Time stamp = frames_.front();
      frames_.pop_front();
      settled_.insert(stamp);
      FrameRecord f;
      f.t = stamp.toSec() - stamp_offset_;
      Eigen::Isometry3d truth;
      try {
        truth = tf2::transformToEigen(tf_.lookupTransform(tanker_frame_, truth_frame_, stamp));
      } catch (const tf2::TransformException& e) {
        ROS_ERROR_STREAM("eval: no truth for frame " << stamp << " (" << e.what()
                                                     << "); frame left out");
        estimates_.erase(stamp);
        ++no_truth_;
        continue;
      }
      f.range_m = truth.translation().norm();
      f.region = aar_geometry::RegionOfRange(f.range_m);
      const auto it = estimates_.find(stamp);
      if (it != estimates_.end() && !it->second->valid)
        estimates_.erase(it);  // no pose: a miss
      else if (it != estimates_.end()) {
        const auto& est = *it->second;
        Eigen::Isometry3d estimated;
        tf2::fromMsg(est.pose, estimated);
        const aar_geometry::PoseError e = aar_geometry::ComputePoseError(truth, estimated);
        f.estimated = true;
        f.error = {e.position_m.x(),
                   e.position_m.y(),
                   e.position_m.z(),
                   aar_geometry::RadToDeg(e.orientation_rad.roll),
                   aar_geometry::RadToDeg(e.orientation_rad.pitch),
                   aar_geometry::RadToDeg(e.orientation_rad.yaw)};
        f.converged = est.converged;
        f.iterations = static_cast<int>(est.iterations);
        f.rms = est.rms;
        f.registration_ms = est.registration_ms;
        aar_msgs::PoseError msg;
        msg.header = est.header;
        msg.region = static_cast<uint8_t>(f.region);
        msg.range_m = f.range_m;
        msg.x_m = f.error[0], msg.y_m = f.error[1], msg.z_m = f.error[2];
        msg.roll_deg = f.error[3], msg.pitch_deg = f.error[4], msg.yaw_deg = f.error[5];
        error_pub_.publish(msg);
        estimates_.erase(it);
      }
      records_.push_back(f);
      out_ << aar_eval::FrameCsvRow(f) << "\n" << std::flush;
      const int k = static_cast<int>(records_.size());
      const double position =
          std::sqrt(f.error[0] * f.error[0] + f.error[1] * f.error[1] + f.error[2] * f.error[2]);
      if (f.estimated) position_sum_ += position, ++estimated_;
      if (k % 10 == 1 || !f.estimated) {
        std::ostringstream line;
        line << "eval: frame " << k
             << (expected_frames_ > 0 ? " of " + std::to_string(expected_frames_) : "") << ", "
             << std::fixed << std::setprecision(1) << f.range_m << " m (region "
             << aar_geometry::RegionName(f.region) << "): " << std::setprecision(3);
        if (f.estimated)
          line << "error " << position << " m";
        else
          line << "MISSED";
        if (estimated_ > 0)
          line << "; running mean " << position_sum_ / estimated_ << " m over " << estimated_
               << " estimates";
        ROS_INFO_STREAM(line.str());
      }
    }
  }

  ros::NodeHandle nh_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener listener_;
  ros::Publisher error_pub_;
  ros::Subscriber frame_sub_, estimate_sub_;
  std::mutex mutex_;
  std::deque<ros::Time> frames_;
  std::set<ros::Time> settled_;
  std::map<ros::Time, aar_msgs::PoseEstimate::ConstPtr> estimates_;
  std::vector<FrameRecord> records_;
  std::ofstream out_;
  std::string path_, truth_frame_, tanker_frame_;
  double stamp_offset_ = 1.0;
  int expected_frames_ = 0;
  int no_truth_ = 0;
  double position_sum_ = 0.0;  // [m] running mean of the position error's norm
  int estimated_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "eval");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<EvalNode> node;
  try {
    node = std::make_unique<EvalNode>(nh, pnh);
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
