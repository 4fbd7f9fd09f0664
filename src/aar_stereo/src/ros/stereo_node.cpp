#include "aar_stereo/ros/stereo_node.h"

#include <aar_ros_common/param_reader.h>

#include <sensor_msgs/PointCloud2.h>
#include <stereo_msgs/DisparityImage.h>

#include "aar_stereo/ros/conversions.h"

namespace aar_stereo {

StereoNodeOptions LoadStereoNodeOptions(const ros::NodeHandle& nh) {
  StereoNodeOptions o;
  aar_ros_common::ParamReader params(nh);
  o.approximate_sync = params.Get("approximate_sync", o.approximate_sync);
  o.queue_size = params.Get("queue_size", o.queue_size);
  params.Check(o.queue_size >= 1, "queue_size", "must be at least 1");
  // Everything else in ~ must be a reconfigurable setting (dynamic_reconfigure reads those) or
  // diagnostic_updater's period: a typo would otherwise be ignored.
  params.Allow("diagnostic_period");
  for (const auto& p : StereoConfig::__getParamDescriptions__()) params.Allow(p->name);
  params.AllowSubNamespaces();  // dynamic_reconfigure's own
  params.RejectUnknown();
  return o;
}

StereoOptions ToStereoOptions(StereoConfig& c) {
  c.block_size |= 1;  // odd
  if (c.matcher == Stereo_block_matching && c.block_size < 5) c.block_size = 5;
  c.prefilter_size |= 1;
  c.num_disparities = ((c.num_disparities + 15) / 16) * 16;
  StereoOptions o;
  o.matcher = c.matcher == Stereo_semi_global ? Matcher::kSemiGlobal : Matcher::kBlockMatching;
  o.block_size = c.block_size;
  o.num_disparities = c.num_disparities;
  o.min_disparity = c.min_disparity;
  o.prefilter_size = c.prefilter_size;
  o.prefilter_cap = c.prefilter_cap;
  o.texture_threshold = c.texture_threshold;
  o.uniqueness_ratio = c.uniqueness_ratio;
  o.speckle_window_size = c.speckle_window_size;
  o.speckle_range = c.speckle_range;
  o.disp12_max_diff = c.disp12_max_diff;
  o.sgbm_p1 = c.sgbm_p1;
  o.sgbm_p2 = c.sgbm_p2;
  o.sgbm_full_dp = c.sgbm_full_dp;
  o.max_range = c.max_range;
  o.decimation = c.decimation == Stereo_none         ? Decimation::kNone
                 : c.decimation == Stereo_voxel_grid ? Decimation::kVoxelGrid
                                                     : Decimation::kEveryNth;
  o.keep_every = c.keep_every;
  o.voxel_size = c.voxel_size;
  if (c.organized && o.decimation != Decimation::kNone) c.organized = false;
  o.organized = c.organized;
  o.intensity = c.intensity;
  return o;
}

StereoNode::StereoNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                       const StereoNodeOptions& options)
    : nh_(nh),
      private_nh_(private_nh),
      options_(options),
      reconfigure_(private_nh),
      diagnostics_(nh, private_nh) {
  reconfigure_.setCallback(
      [this](StereoConfig& config, uint32_t level) { OnReconfigure(config, level); });
  if (options_.approximate_sync) {
    approximate_ = std::make_unique<message_filters::Synchronizer<ApproximatePolicy>>(
        ApproximatePolicy(options_.queue_size), left_sub_, left_info_sub_, right_sub_,
        right_info_sub_);
    approximate_->registerCallback(&StereoNode::OnFrame, this);
  } else {
    exact_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
        ExactPolicy(options_.queue_size), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
    exact_->registerCallback(&StereoNode::OnFrame, this);
  }
  // Arrival bookkeeping for the "stamps never match" report.
  auto note = [this](int i, const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(input_mutex_);
    last_stamp_[i] = stamp;
    last_arrival_[i] = ros::WallTime::now();
  };
  left_sub_.registerCallback(boost::function<void(const Image::ConstPtr&)>(
      [note](const Image::ConstPtr& m) { note(0, m->header.stamp); }));
  left_info_sub_.registerCallback(boost::function<void(const Info::ConstPtr&)>(
      [note](const Info::ConstPtr& m) { note(1, m->header.stamp); }));
  right_sub_.registerCallback(boost::function<void(const Image::ConstPtr&)>(
      [note](const Image::ConstPtr& m) { note(2, m->header.stamp); }));
  right_info_sub_.registerCallback(boost::function<void(const Info::ConstPtr&)>(
      [note](const Info::ConstPtr& m) { note(3, m->header.stamp); }));

  // Lazy: subscribe to the cameras only while someone listens to an output.
  auto connect = [this](const ros::SingleSubscriberPublisher&) { Connect(); };
  std::lock_guard<std::mutex> lock(connect_mutex_);
  disparity_pub_ = nh_.advertise<stereo_msgs::DisparityImage>("disparity", 1, connect, connect);
  points_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points2", 1, connect, connect);

  diagnostics_.setHardwareID("stereo pair " + nh_.resolveName("left") + ", " +
                             nh_.resolveName("right"));
  diagnostics_.add("stereo", this, &StereoNode::Diagnose);
  input_timer_ = nh_.createWallTimer(ros::WallDuration(2.0), &StereoNode::CheckInputs, this);
}

StereoNode::~StereoNode() {
  // Inputs and timer first: no callback may run into members being destroyed.
  input_timer_.stop();
  left_sub_.unsubscribe();
  left_info_sub_.unsubscribe();
  right_sub_.unsubscribe();
  right_info_sub_.unsubscribe();
}

void StereoNode::Connect() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  const bool wanted = disparity_pub_.getNumSubscribers() > 0 || points_pub_.getNumSubscribers() > 0;
  if (wanted && !subscribed_) {
    const uint32_t q = static_cast<uint32_t>(options_.queue_size);
    left_sub_.subscribe(nh_, "left/image_rect", q);
    left_info_sub_.subscribe(nh_, "left/camera_info", q);
    right_sub_.subscribe(nh_, "right/image_rect", q);
    right_info_sub_.subscribe(nh_, "right/camera_info", q);
    {
      std::lock_guard<std::mutex> input(input_mutex_);
      last_frame_ = ros::WallTime::now();
    }
    subscribed_ = true;
  } else if (!wanted && subscribed_) {
    left_sub_.unsubscribe();
    left_info_sub_.unsubscribe();
    right_sub_.unsubscribe();
    right_info_sub_.unsubscribe();
    subscribed_ = false;
  }
}

void StereoNode::OnReconfigure(StereoConfig& config, uint32_t) {
  try {
    auto processor = std::make_unique<StereoProcessor>(ToStereoOptions(config));
    std::lock_guard<std::mutex> lock(mutex_);
    processor_ = std::move(processor);
  } catch (const std::exception& e) {
    ROS_ERROR_STREAM("stereo: settings rejected, keeping the previous ones: " << e.what());
  }
}

void StereoNode::OnFrame(const Image::ConstPtr& left, const Info::ConstPtr& left_info,
                         const Image::ConstPtr& right, const Info::ConstPtr& right_info) {
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    last_frame_ = ros::WallTime::now();
  }
  try {
    const StereoGeometry geometry = ToStereoGeometry(*left_info, *right_info);
    const cv::Mat l = ToMono8(*left, "left"), r = ToMono8(*right, "right");
    std::lock_guard<std::mutex> lock(mutex_);
    if (!processor_) return;
    const StereoResult result = processor_->Process(l, r, geometry);
    std_msgs::Header header = left->header;
    if (disparity_pub_.getNumSubscribers() > 0) {
      disparity_pub_.publish(
          ToDisparityMsg(result, processor_->options(), geometry, result.valid_window, header));
    }
    if (points_pub_.getNumSubscribers() > 0)
      points_pub_.publish(ToPointCloud2Msg(result.cloud, header));
    ++frames_;
    {
      std::lock_guard<std::mutex> stats(stats_mutex_);
      last_timings_ = result.timings;
      last_points_ = result.cloud.xyz.size();
    }
    ROS_DEBUG_STREAM("stereo: frame " << header.stamp << ": " << result.cloud.xyz.size()
                                      << " points; matching " << result.timings.matching_ms
                                      << " ms, reprojection " << result.timings.reprojection_ms
                                      << " ms, decimation " << result.timings.decimation_ms
                                      << " ms");
    ROS_INFO_STREAM_THROTTLE(10.0, "stereo: " << frames_
                                              << " frames; last: " << result.cloud.xyz.size()
                                              << " points in " << result.timings.total_ms << " ms");
  } catch (const std::exception& e) {
    ++skipped_;
    {
      std::lock_guard<std::mutex> stats(stats_mutex_);
      last_error_ = e.what();
    }
    // Throttled per reason, not per call site: a new problem is reported at once.
    if (errors_.ShouldLog(e.what()))
      ROS_ERROR_STREAM("stereo: frame " << left->header.stamp << " skipped: " << e.what());
  }
}

void StereoNode::CheckInputs(const ros::WallTimerEvent&) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const ros::WallDuration window(4.0);
  bool all_arriving = true;
  for (const auto& t : last_arrival_) all_arriving &= !t.isZero() && now - t < window;
  if (all_arriving && now - last_frame_ > window) {
    ROS_ERROR_STREAM_THROTTLE(
        10.0, "stereo: images and camera infos arrive but their stamps never match "
                  << "(left image " << last_stamp_[0] << ", left info " << last_stamp_[1]
                  << ", right image " << last_stamp_[2] << ", right info " << last_stamp_[3]
                  << "); exact sync needs all four equal: set ~approximate_sync true for "
                     "cameras that are not synchronised");
  }
  diagnostics_.update();
}

void StereoNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  // Judged on the frames since the previous report, so a warning clears once inputs are good.
  const uint64_t frames = frames_ - reported_frames_, skipped = skipped_ - reported_skipped_;
  reported_frames_ = frames_;
  reported_skipped_ = skipped_;
  if (skipped > 0 && frames == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "every recent frame skipped: " + last_error_);
  } else if (skipped > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "frames skipped, last because: " + last_error_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, frames > 0 ? "processing" : "no input");
  }
  status.add("frames", static_cast<uint64_t>(frames_));
  status.add("skipped frames", static_cast<uint64_t>(skipped_));
  status.add("points (last frame)", last_points_);
  status.add("matching [ms]", last_timings_.matching_ms);
  status.add("reprojection [ms]", last_timings_.reprojection_ms);
  status.add("decimation [ms]", last_timings_.decimation_ms);
  status.add("total [ms]", last_timings_.total_ms);
}

}  // namespace aar_stereo
