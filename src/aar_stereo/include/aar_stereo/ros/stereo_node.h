#pragma once

#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>
#include <aar_ros_common/error_throttle.h>
#include <aar_ros_common/estimate_listener.h>
#include <aar_ros_common/frame_ledger.h>
#include <aar_ros_common/node_options.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/stage.h>
#include <aar_ros_common/stamp_order.h>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>

#include <aar_stereo/StereoConfig.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "aar_stereo/stereo.h"

namespace aar_stereo {

// Matching only where the receiver can be: the projection of the predicted receiver's bounding
// box and of the boom's collision parts (the boom's points are what the occlusion stage removes,
// and it judges them with the receiver's), grown by a margin. The prediction is the latest
// aar/pose_estimate of a live track moved on to the images' stamp; without one (acquisition, a
// lost track, no estimate yet, missing tf) the whole image is matched.
struct StereoRoiOptions {
  bool enabled = false;
  int margin = 16;               // [px] around the projected bounds
  double receiver_margin = 2.0;  // [m] the receiver's bounding box grown by this: prediction error
  bool include_boom = true;      // the boom's collision parts (needs ~robot_description and tf)
  // [s wall] wait for the previous frame's estimate (repeatable lockstep runs; 0 in real time).
  double estimate_wait = 0.2;
  aar_description::ReceiverDescription receiver;  // ~receiver (default: the C-12)
};

// Stereo's defaults of the shared keys: an estimate older than 0.5 s gives the whole image; tf
// (the camera's and the boom links') is waited for 0.05 s. A tf_fallback_age > 0 uses the latest
// transform when tf has nothing at the images' stamp yet: a region of interest needs no exact boom
// pose, and waiting for tf that comes through a relay cost real-time replays ~25 ms a frame.
inline aar_ros_common::CommonNodeOptions StereoCommonDefaults() {
  aar_ros_common::CommonNodeOptions c;
  c.estimate_max_age = 0.5;
  c.tf_timeout = 0.05;
  return c;
}

struct StereoNodeOptions {
  bool approximate_sync = false;  // pair images whose stamps differ (unsynchronised cameras)
  // [s] approximate sync: a pair whose four stamps (images, camera infos) span more than this
  // is dropped, named: halves taken this far apart (one camera lagging) give a wrong cloud.
  double max_pair_skew = 0.01;
  // true: image_rect is rectified upstream (image_proc) from raw images whose camera infos
  // (D, R) describe the raw cameras; false: a non-zero D is warned about (distorted images fed as
  // image_rect without rectification).
  bool rectified_upstream = false;
  int queue_size = 5;  // synchroniser queue per input (subscribers: at least 30 with newest_wins)
  // true: pairs are matched on a thread of their own and a pair that arrives while another waits
  // replaces it, counted (real time: replay.launch realtime:=true sets it); false: matched in the
  // subscriber callback, queueing (lockstep runs and slow replays keep every pair).
  bool newest_wins = false;
  // OpenCV's worker threads (cv::setNumThreads, process-wide); -1: OpenCV's default (all cores).
  int opencv_threads = -1;
  // [s] a pair older than this (ROS time now minus its stamp) when its turn comes is dropped:
  // latency stays bounded when the graph falls behind a live camera. 0: off (lockstep and slow
  // replays never fall behind).
  double max_frame_age = 0.0;
  // [s] a pair stamped further ahead than this of both the clock and the last pair taken is
  // dropped, named (as registration's max_stamp_lead): taken, it would make every pair after it
  // "out of order" until the clock passed it. Ahead of the clock alone is not enough: in a fast
  // replay the clock's callback can wait behind busy ones.
  double max_stamp_lead = 1.0;
  StereoRoiOptions roi;
  aar_ros_common::CommonNodeOptions common = StereoCommonDefaults();
};

// Reads the node's own (non-reconfigurable) ~parameters and rejects unknown ~parameters; the
// matcher settings are read by the dynamic_reconfigure server, and checked here (types, ranges,
// odd sizes). Throws std::invalid_argument.
StereoNodeOptions LoadStereoNodeOptions(const ros::NodeHandle& private_nh);
StereoNodeOptions LoadStereoNodeOptions(aar_ros_common::ParamReader& params);

// The matcher settings as the dynamic_reconfigure server starts with them: the defaults, and each
// ~key that is set with the setting's type.
StereoConfig LoadStereoConfig(const aar_ros_common::ParamReader& params);

// Matcher settings from a (possibly user-edited) reconfigure request, sanitised as
// stereo_image_proc does: odd block sizes, disparity range a multiple of 16. Writes the values
// used back into `config` so the user sees them.
StereoOptions ToStereoOptions(StereoConfig& config);

// Where a frame is matched: the region of interest (none: the whole image) and, for the sparse
// matcher, the disparity bounds of the predicted receiver and of the boom.
struct FrameRegion {
  std::optional<cv::Rect> roi;
  std::vector<DisparityZone> zones;
};

// Subscribes (lazily) to left/ and right/ image_rect + camera_info in its namespace, publishes
// disparity and points2 (in the left optical frame). Pairs are matched on a thread of their own,
// one at a time: a pair that arrives while another waits replaces it (counted on /diagnostics).
class StereoNode {
 public:
  StereoNode(ros::NodeHandle nh, ros::NodeHandle private_nh, const StereoNodeOptions& options);
  ~StereoNode();

 private:
  using Image = sensor_msgs::Image;
  using Info = sensor_msgs::CameraInfo;
  using ExactPolicy = message_filters::sync_policies::ExactTime<Image, Info, Image, Info>;
  using ApproximatePolicy =
      message_filters::sync_policies::ApproximateTime<Image, Info, Image, Info>;

  void Connect();
  struct Pair {
    Image::ConstPtr left, right;
    Info::ConstPtr left_info, right_info;
  };
  void OnFrame(const Image::ConstPtr& left, const Info::ConstPtr& left_info,
               const Image::ConstPtr& right, const Info::ConstPtr& right_info);
  void OnUnpaired(const Image::ConstPtr& left, const Info::ConstPtr& left_info,
                  const Image::ConstPtr& right, const Info::ConstPtr& right_info);
  // Empty, or why `stamp` is too far ahead of the clock (max_stamp_lead).
  std::string StampAhead(const ros::Time& stamp) const;
  void Match(Pair& pair);
  void OnReconfigure(StereoConfig& config, uint32_t level);
  void WarnIfDistorted(const Info& left, const Info& right);
  void CheckInputs(const ros::WallTimerEvent&);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  // The region of interest for a frame, or none (whole image) with `why` saying why.
  FrameRegion Roi(const std_msgs::Header& header, const StereoGeometry& geometry, std::string* why);
  // T_target_source at `stamp` (tf_timeout), else the latest within tf_fallback_age.
  std::optional<Eigen::Isometry3d> Transform(const std::string& target, const std::string& source,
                                             const ros::Time& stamp, std::string* why);

  ros::NodeHandle nh_, private_nh_;
  StereoNodeOptions options_;
  std::mutex mutex_;  // guards processor_ against reconfiguration mid-frame
  std::unique_ptr<StereoProcessor> processor_;
  dynamic_reconfigure::Server<StereoConfig> reconfigure_;

  std::mutex connect_mutex_;
  bool subscribed_ = false;
  message_filters::Subscriber<Image> left_sub_, right_sub_;
  message_filters::Subscriber<Info> left_info_sub_, right_info_sub_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_;
  ros::Publisher disparity_pub_, points_pub_;

  // Input health: last arrival per input, for "stamps never match" reports.
  std::mutex input_mutex_;
  ros::Time last_stamp_[4];
  ros::WallTime last_arrival_[4];
  ros::WallTime last_frame_;
  ros::WallTimer input_timer_;

  diagnostic_updater::Updater diagnostics_;
  std::atomic<uint64_t> frames_{0}, skipped_{0};
  std::atomic<uint64_t> distorted_{0};  // pairs whose camera infos had a non-zero D
  // Every pair taken in: passed or dropped, why; the one count of drops (/diagnostics "ledger: ").
  aar_ros_common::FrameLedger ledger_;
  aar_ros_common::StampOrder order_;  // pairs are taken in stamp order
  ros::Time last_taken_;              // the last pair's stamp (OnFrame: the synchroniser's lock)
  std::mutex stats_mutex_;
  StereoTimings last_timings_;
  size_t last_points_ = 0;
  std::string last_error_;
  uint64_t reported_frames_ = 0, reported_skipped_ = 0;  // at the previous diagnostics report
  aar_ros_common::ErrorThrottle errors_;
  SparseMatches last_samples_;  // the sparse matcher's last grid and refusals

  // Region of interest (options_.roi.enabled)
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<aar_ros_common::EstimateListener> estimates_;
  Eigen::AlignedBox3d receiver_box_;              // [m] receiver frame
  std::optional<aar_geometry::RobotModel> boom_;  // none: the boom is left out of the roi
  std::optional<ros::Time> previous_stamp_;
  uint64_t roi_frames_ = 0;  // frames matched in a region of interest (stats_mutex_)
  double last_roi_fraction_ = 1.0;
  std::string last_roi_why_;  // why the last frame was matched whole

  // Last: the matching thread (stopped first in the destructor) uses the members above.
  std::unique_ptr<aar_ros_common::Stage<Pair>> stage_;
};

}  // namespace aar_stereo
