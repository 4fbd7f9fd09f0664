#include "aar_eval/ros/eval_node.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <aar_msgs/PoseError.h>
#include <aar_ros_common/frame_ledger.h>
#include <aar_ros_common/tf_bridge.h>

#include "aar_eval/ros/conversions.h"

namespace aar_eval {
namespace {

double WallNow() { return ros::WallTime::now().toSec(); }

bool Finite(const aar_msgs::PoseEstimate& e) {
  const auto& p = e.pose.position;
  const auto& q = e.pose.orientation;
  for (double v : {p.x, p.y, p.z, q.x, q.y, q.z, q.w})
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

EvalNode::EvalNode(ros::NodeHandle nh, const EvalNodeOptions& options)
    : nh_(nh),
      options_(options),
      tf_(ros::Duration(120.0)),
      listener_(tf_),
      evaluator_(options.stamp_offset, options.expected_frames, options.settle_after),
      publisher_(options.estimate_publisher) {
  std::filesystem::create_directories(options_.output_dir);
  path_ = options_.output_dir + "/frames.csv";
  ledger_path_ = options_.output_dir + "/ledger.csv";
  out_.open(path_);
  if (!out_) throw std::runtime_error(path_ + ": cannot be written");
  ledger_out_.open(ledger_path_);
  if (!ledger_out_) throw std::runtime_error(ledger_path_ + ": cannot be written");
  Write(out_, path_, FrameCsvHeader());
  Write(ledger_out_, ledger_path_, LedgerCsvHeader());
  if (write_failed_) throw std::runtime_error(path_ + ": the first line could not be written");
  error_pub_ = nh_.advertise<aar_msgs::PoseError>("aar/pose_error", 10);
  // Long queues: a frame dropped here would have neither a row nor a log line (small messages).
  frame_sub_ = nh_.subscribe("stereo/left/camera_info", 100, &EvalNode::OnFrame, this);
  estimate_sub_ = nh_.subscribe("aar/pose_estimate", 100, &EvalNode::OnEstimate, this);
  outcome_sub_ =
      nh_.subscribe(aar_ros_common::kFrameOutcomeTopic, 1000, &EvalNode::OnOutcome, this);
  visibility_sub_ = nh_.subscribe<aar_msgs::Visibility>(
      "sim/visibility", 100,
      [this](const aar_msgs::Visibility::ConstPtr& msg) { OnVisibility(msg, 0); });
  for (size_t i = 1; i < options_.rigs.size(); ++i)
    rig_visibility_subs_.push_back(nh_.subscribe<aar_msgs::Visibility>(
        "sim/" + options_.rigs[i] + "/visibility", 100,
        [this, i](const aar_msgs::Visibility::ConstPtr& msg) { OnVisibility(msg, i); }));
  tf_sub_ = nh_.subscribe("/tf", 1000, &EvalNode::OnTf, this);
  // A static truth (a test's) holds at every stamp: no outage to guard against.
  tf_static_sub_ = nh_.subscribe<tf2_msgs::TFMessage>(
      "/tf_static", 100, [this](const tf2_msgs::TFMessage::ConstPtr& tf) {
        std::lock_guard<std::mutex> lock(truth_mutex_);
        for (const auto& t : tf->transforms)
          truth_static_ |= t.child_frame_id == options_.truth_frame;
      });
  // Frames whose estimate never comes settle on time, also when nothing else arrives.
  settle_timer_ = nh_.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) {
    std::lock_guard<std::mutex> lock(mutex_);
    Settle();
  });
}

EvalNode::~EvalNode() {
  settle_timer_.stop();
  frame_sub_.shutdown();
  estimate_sub_.shutdown();
  outcome_sub_.shutdown();
  visibility_sub_.shutdown();
  for (auto& sub : rig_visibility_subs_) sub.shutdown();
  tf_sub_.shutdown();
  tf_static_sub_.shutdown();
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
  if (while_strangers_ > 0) {
    std::cout << "eval: ignored " << while_strangers_ << " estimates while another node than "
              << publisher_ << " was linked to the estimates' topic\n";
  }
  for (const auto& [caller, n] : other_publishers_)
    std::cout << "eval: ignored " << n << " estimates from " << caller << " (not " << publisher_
              << ")\n";
  std::cout << "eval: ledger: " << LedgerSummary(evaluator_.ledger()) << " (" << ledger_path_
            << ")\n";
  std::cout << "eval: wrote " << evaluator_.records().size() << " frames to " << path_
            << (write_failed_ ? " (INCOMPLETE: a write failed)" : "") << std::endl;
}

// Truth only from a sample close to the frame: tf2 would interpolate across an outage.
std::optional<Eigen::Isometry3d> EvalNode::Truth(int64_t stamp_ns, std::string* error) {
  {
    std::lock_guard<std::mutex> lock(truth_mutex_);
    const int64_t tolerance = static_cast<int64_t>(options_.truth_tolerance * 1e9);
    const auto near = truth_stamps_.lower_bound(stamp_ns - tolerance);
    if (!truth_static_ && (near == truth_stamps_.end() || *near > stamp_ns + tolerance)) {
      std::ostringstream s;
      s << "no truth sample within truth_tolerance (" << options_.truth_tolerance
        << " s) of the frame: truth is not interpolated across a gap";
      *error = s.str();
      return std::nullopt;
    }
  }
  return aar_ros_common::LookupTransform(tf_, options_.tanker_frame, options_.truth_frame,
                                         ToRosTime(stamp_ns), 0.0, "the frame's stamp", error);
}

// Ready once a truth sample after the frame's came: tf2 then interpolates at ratio 0 between the
// frame's sample and the next, the lookup eval always made, so per-frame results stay identical
// to the last digit across versions (the frame's sample alone differs by ~1e-15 m).
bool EvalNode::TruthReady(int64_t stamp_ns) {
  int64_t next = stamp_ns;  // the first truth sample after the frame, once the tf buffer has it
  {
    std::lock_guard<std::mutex> lock(truth_mutex_);
    if (!truth_static_) {
      const auto after = truth_stamps_.upper_bound(stamp_ns);
      if (after == truth_stamps_.end()) return false;
      next = *after;
    }
  }
  return tf_.canTransform(options_.tanker_frame, options_.truth_frame, ToRosTime(next));
}

void EvalNode::OnTf(const tf2_msgs::TFMessage::ConstPtr& tf) {
  std::lock_guard<std::mutex> lock(truth_mutex_);
  for (const auto& t : tf->transforms)
    if (t.child_frame_id == options_.truth_frame) truth_stamps_.insert(ToNs(t.header.stamp));
  // Kept for two minutes of stamps before the newest, as the tf buffer keeps them.
  while (!truth_stamps_.empty() && *truth_stamps_.begin() < *truth_stamps_.rbegin() - 120000000000)
    truth_stamps_.erase(truth_stamps_.begin());
}

void EvalNode::OnFrame(const sensor_msgs::CameraInfo::ConstPtr& info) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int64_t newest = evaluator_.newest_frame_ns();
  switch (evaluator_.AddFrame(ToNs(info->header.stamp), WallNow())) {
    case Evaluator::FrameStatus::kOlder:
      ROS_WARN_STREAM("eval: frame " << info->header.stamp << " is older than the last one ("
                                     << ToRosTime(newest) << "): ignored; did the clock jump?");
      return;
    case Evaluator::FrameStatus::kRepeat:
      return;  // the same frame again
    case Evaluator::FrameStatus::kNew:
      break;
  }
  Settle();
}

bool EvalNode::FromExpectedPublisher(const std::string& publisher, const ros::Time& stamp) {
  if (publisher_.empty()) {
    publisher_ = publisher;
    ROS_INFO_STREAM("eval: taking estimates from " << publisher_
                                                   << " (the first publisher heard; set "
                                                      "~estimate_publisher to name it)");
  }
  if (publisher == publisher_) return true;
  if (other_publishers_[publisher]++ == 0 || other_publishers_[publisher] % 100 == 0) {
    ROS_WARN_STREAM("eval: an estimate for " << stamp << " from " << publisher
                                             << ", not from the registration (" << publisher_
                                             << "): ignored (" << other_publishers_[publisher]
                                             << " from it so far)");
  }
  return false;
}

bool EvalNode::NoStranger(const ros::Time& stamp) {
  if (!check_) check_.emplace(estimate_sub_.getTopic(), publisher_);
  const std::vector<std::string> strangers =
      check_->StrangersIfChanged(estimate_sub_.getNumPublishers());
  if (strangers.empty()) return true;
  if (while_strangers_++ % 100 == 0) {
    ROS_ERROR_STREAM("eval: another node is linked to "
                     << estimate_sub_.getTopic() << " at " << check_->Describe(strangers)
                     << ": the estimate for " << stamp << " cannot be told from its: ignored ("
                     << while_strangers_ << " so far)");
  }
  return false;
}

void EvalNode::OnEstimate(const ros::MessageEvent<aar_msgs::PoseEstimate const>& event) {
  const aar_msgs::PoseEstimate::ConstPtr& estimate = event.getConstMessage();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!FromExpectedPublisher(event.getPublisherName(), estimate->header.stamp) ||
      !NoStranger(estimate->header.stamp)) {
    return;
  }
  if (estimate->valid && !Finite(*estimate)) {
    ROS_ERROR_STREAM("eval: estimate for " << estimate->header.stamp << " from "
                                           << event.getPublisherName()
                                           << " has a pose that is not finite: ignored");
    return;
  }
  const int64_t stamp = ToNs(estimate->header.stamp);
  if (!evaluator_.AddEstimate(stamp, ToEstimate(*estimate))) {
    ROS_WARN_STREAM("eval: estimate for " << estimate->header.stamp
                                          << " came after its frame was settled: ignored");
    return;
  }
  estimate_headers_[stamp] = estimate->header;
  Settle();
}

void EvalNode::OnOutcome(const aar_msgs::FrameOutcome::ConstPtr& msg) {
  StageOutcome o;
  o.stage = msg->stage;
  o.dropped = msg->outcome == aar_msgs::FrameOutcome::DROPPED;
  o.reason = msg->reason;
  o.detail = msg->detail;
  std::lock_guard<std::mutex> lock(mutex_);
  evaluator_.AddOutcome(ToNs(msg->header.stamp), o);
  Settle();
}

void EvalNode::OnVisibility(const aar_msgs::Visibility::ConstPtr& msg, size_t rig) {
  const size_t n = msg->camera.size();
  std::vector<CameraVisibility> views;
  for (size_t i = 0; i < n && msg->silhouette_px.size() == n && msg->visible_px.size() == n; ++i) {
    if (msg->visible_px[i] > msg->silhouette_px[i]) break;
    views.push_back(
        {static_cast<int>(msg->silhouette_px[i]), static_cast<int>(msg->visible_px[i])});
  }
  if (views.size() != n || n == 0) {
    ROS_WARN_STREAM("eval: left out a malformed visibility of stamp "
                    << msg->header.stamp << ": " << n << " cameras, " << msg->silhouette_px.size()
                    << " silhouettes, " << msg->visible_px.size()
                    << " visible counts (one each, visible at most the silhouette)");
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!evaluator_.AddVisibility(ToNs(msg->header.stamp), views, rig)) {
    ROS_WARN_STREAM("eval: the visibility of stamp " << msg->header.stamp
                                                     << " came after its frame settled: left out");
    return;
  }
  Settle();  // its frame may wait for nothing else
}

void EvalNode::Settle() {
  Record(evaluator_.SettleReady(
      WallNow(), [this](int64_t stamp_ns) { return TruthReady(stamp_ns); },
      [this](int64_t stamp_ns, std::string* error) { return Truth(stamp_ns, error); }));
}

// A results file that cannot be written ends the node: a run must not pass with rows missing.
void EvalNode::Write(std::ofstream& out, const std::string& path, const std::string& line) {
  out << line << "\n" << std::flush;
  if (out || write_failed_) return;
  write_failed_ = true;
  const std::string what = "eval: cannot write " + path + " (" + std::strerror(errno) +
                           "): stopping, the results would be incomplete";
  std::cerr << what << std::endl;
  ROS_FATAL_STREAM(what);
  ros::requestShutdown();
}

void EvalNode::Record(const std::vector<SettledFrame>& settled) {
  for (const SettledFrame& s : settled) {
    Write(ledger_out_, ledger_path_, LedgerCsvRow(s.ledger));
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
    if (s.ledger.outcome == "dropped" && !stopping_) {
      const std::string where = s.ledger.stage + " (" + s.ledger.reason + ")";
      const uint64_t n = ++drops_[where];
      if (drop_log_.ShouldLog(where))
        ROS_WARN_STREAM("eval: frame " << ToRosTime(s.stamp_ns) << " dropped by " << where << ": "
                                       << s.ledger.detail << " (" << n << " so far)");
    }
    const FrameRecord& f = s.record;
    if (f.estimated) error_pub_.publish(ToPoseErrorMsg(f, estimate_header));
    Write(out_, path_, FrameCsvRow(f));
    if (!s.progress.empty()) ROS_INFO_STREAM(s.progress);
  }
}

}  // namespace aar_eval
