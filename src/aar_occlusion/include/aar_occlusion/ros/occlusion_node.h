#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <aar_ros_common/error_throttle.h>
#include <aar_ros_common/frame_ledger.h>
#include <aar_ros_common/node_options.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/point_cloud.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <aar_ros_common/estimate_listener.h>
#include <aar_ros_common/stage.h>

#include <aar_description/receiver_description.h>

#include "aar_occlusion/occlusion_step.h"

namespace aar_occlusion {

// Occlusion's defaults of the shared keys: tf (the cloud's, cameras' and links') waited for
// 0.5 s; an estimate older than 1 s is not used as the predicted pose.
inline aar_ros_common::CommonNodeOptions OcclusionCommonDefaults() {
  aar_ros_common::CommonNodeOptions c;
  c.estimate_max_age = 1.0;
  return c;
}

struct OcclusionNodeOptions {
  OcclusionStepOptions step;                      // culling, margins, the dynamic reference
  aar_description::ReceiverDescription receiver;  // ~receiver (default: the C-12)
  // Frames, the boom's URDF parameter, tf waits, /diagnostics period, estimate age.
  aar_ros_common::CommonNodeOptions common = OcclusionCommonDefaults();
  // true: clouds are culled on a thread of their own and a cloud that arrives while another
  // waits replaces it, counted (real time: replay.launch realtime:=true sets it); false: culled
  // in the subscriber callback, queueing (lockstep runs and slow replays keep every cloud).
  bool newest_wins = false;
  // [s wall] how long to wait for the estimate of the previous cloud (its aar/pose_estimate, then,
  // if it had a pose, tf tanker -> receiver at its stamp): in lockstep it is on its way, and
  // waiting makes runs repeatable.
  double estimate_wait = 0.2;
  // Where the predicted pose comes from: false, the latest estimate as it stands (tf tanker ->
  // receiver; the thesis); true, the latest aar/pose_estimate moved on to the cloud's stamp by
  // its velocity (tracking), which also covers estimates that lag frames behind in real time.
  bool extrapolate_estimate = false;
  double marker_length = 30.0;  // [m] how far the shadow-volume markers reach past the boom
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
OcclusionNodeOptions LoadOcclusionNodeOptions(const ros::NodeHandle& private_nh);
OcclusionNodeOptions LoadOcclusionNodeOptions(aar_ros_common::ParamReader& params);

// The ROS side of OcclusionStep. Per sensed cloud (~points): gathers the tf it needs (cloud,
// cameras, boom links, the latest estimate), runs the step, and publishes the cloud without boom
// points (aar/points_filtered, aar/boom_points), the dynamic reference model
// (aar/reference_cloud), the shadow volumes (aar/shadow_volumes) and diagnostics.
class OcclusionNode {
 public:
  OcclusionNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                const OcclusionNodeOptions& options);
  ~OcclusionNode();

 private:
  // Hands the cloud to the culling thread: a cloud that waits there when a newer one comes is
  // skipped and counted (aar_ros_common::NewestWins).
  void OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void Cull(const sensor_msgs::PointCloud2::ConstPtr& msg);
  // The step's input from the cloud and tf (the cloud's, the cameras', the boom links', the
  // predicted pose); throws std::runtime_error naming the missing transform.
  OcclusionInput GatherInput(const sensor_msgs::PointCloud2& msg,
                             const aar_ros_common::CloudPoints& cloud);
  std::optional<Eigen::Isometry3d> Lookup(const std::string& frame, const ros::Time& stamp,
                                          std::string* error);
  std::optional<Eigen::Isometry3d> PredictedPose(const ros::Time& stamp);
  void ReportError(const std::string& what);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  OcclusionNodeOptions options_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::unique_ptr<aar_ros_common::EstimateListener> estimates_;  // when a pose is predicted
  ros::Publisher filtered_pub_, boom_pub_, reference_pub_, markers_pub_;
  ros::Subscriber cloud_sub_;
  diagnostic_updater::Updater diagnostics_;
  ros::WallTimer diagnostics_timer_;

  std::mutex mutex_;
  std::unique_ptr<OcclusionStep> step_;
  bool markers_stale_ = true;

  aar_ros_common::ErrorThrottle errors_;
  std::mutex report_mutex_;                  // guards what diagnostics read
  std::string last_frame_error_;             // empty when the last frame was culled as configured
  std::string last_reference_error_;         // empty when the last reference was built
  std::optional<ros::Time> previous_stamp_;  // of the previous cloud
  uint64_t frames_ = 0, unculled_frames_ = 0, reference_failures_ = 0;
  double last_ms_ = 0.0;
  size_t last_boom_points_ = 0, last_reference_both_ = 0;
  size_t last_propeller_points_ = 0;  // of the boom points removed: on the propeller discs
  size_t last_gated_points_ = 0;      // dropped by the receiver gate
  // Every cloud taken in: passed on or dropped, why; the one count of drops.
  aar_ros_common::FrameLedger ledger_;

  // Last: the culling thread (stopped first in the destructor) uses the members above.
  std::unique_ptr<aar_ros_common::Stage<sensor_msgs::PointCloud2::ConstPtr>> stage_;
};

}  // namespace aar_occlusion
