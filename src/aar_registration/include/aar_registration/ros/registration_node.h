#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <aar_geometry/triangle_mesh.h>
#include <aar_ros_common/error_throttle.h>
#include <aar_ros_common/frame_ledger.h>
#include <aar_ros_common/node_options.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/stage.h>
#include <aar_ros_common/stamp_order.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <aar_description/receiver_description.h>

#include "aar_registration/registrar.h"
#include "aar_registration/ros/outline_inputs.h"
#include "aar_registration/ros/rig_gather.h"

namespace aar_registration {

struct RegistrationNodeOptions {
  RegistrarOptions registrar;  // reference kind, sampling, nominal pose, ICP, seed policy
  aar_description::ReceiverDescription receiver;  // ~receiver (default: the C-12)
  // Frames (tanker, receiver: the estimate, cameras), the boom's URDF parameter (the outline's
  // mask), tf waits (the sensed cloud's; the fallback age: the outline's boom mask from the
  // links' latest tf when the images' own has not come, real time), the /diagnostics period.
  // Registration makes the estimate: it reads none (estimate_max_age 0).
  aar_ros_common::CommonNodeOptions common;
  std::string truth_frame = "receiver_truth";  // only for the rviz model at truth
  // true: clouds are registered on a thread of their own and a cloud that arrives while another
  // waits replaces it, counted (real time: replay.launch realtime:=true sets it); false:
  // registered in the subscriber callback, queueing (lockstep runs and slow replays).
  bool newest_wins = false;
  // [s wall] reference: topic: a cloud without a reference of its stamp this long is answered
  // with an invalid estimate.
  double reference_timeout = 2.0;
  // [s] a cloud stamped further ahead of the node's clock is refused: its pose on tf would make
  // every later tanker -> receiver transform TF_OLD_DATA. Stamp 0 is refused too.
  double max_stamp_lead = 1.0;
  // false: the tanker flies no boom (the boom hidden to measure its cost): the outline masks none.
  bool model_boom = true;
  // The stereo rigs fused (issue 44, docs/ARCHITECTURE.md), in order. The first is the one of
  // `points`, aar/reference_cloud and left/..., right/...; a further rig R's clouds come on
  // R/aar/points_filtered and R/aar/reference_cloud, its images on R/{left,right}/image_rect and
  // camera_info. One rig: today's graph, nothing gathered.
  std::vector<std::string> rigs = {"stereo"};
  // [s wall] more than one rig: a frame is registered when every rig's cloud (and reference) has
  // come, or this long after its first came, with those that did (the others counted missing).
  double rig_wait = 0.5;
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
RegistrationNodeOptions LoadRegistrationNodeOptions(const ros::NodeHandle& private_nh);
RegistrationNodeOptions LoadRegistrationNodeOptions(aar_ros_common::ParamReader& params);

// The ROS side of Registrar: each sensed cloud (~points, any frame with tf to the tanker), paired
// by stamp with its reference (aar/reference_cloud) when the reference is a topic, goes to the
// registrar; the pose goes out as aar/receiver_pose (with its covariance), aar/pose_estimate
// and tf; the track's health on /diagnostics.
class RegistrationNode {
 public:
  RegistrationNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                   const RegistrationNodeOptions& options);
  ~RegistrationNode();

 private:
  // A frame's sensed clouds, one per rig (null: the rig's did not come), each with the reference
  // built for its stamp when the reference is a topic.
  struct Input {
    ros::Time stamp;
    std::vector<RigGather::Cloud> clouds;
  };
  void OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void Process(const Input& input);
  void Register(const Input& input);  // mutex_ held
  // The frame's sensed points in the tanker frame, every rig's in rig order; throws with why not.
  std::vector<Eigen::Vector3d> SensedInTanker(const Input& input);
  // The frame's images for the outline, every rig's that came (nullopt: the first rig's did not).
  std::optional<OutlineFrame> OutlineOf(const ros::Time& stamp);
  void OnPair(const sensor_msgs::PointCloud2::ConstPtr& points,
              const sensor_msgs::PointCloud2::ConstPtr& reference);
  // More than one rig: rig `rig`'s cloud and reference into the gather.
  void OnRigPair(size_t rig, const sensor_msgs::PointCloud2::ConstPtr& points,
                 const sensor_msgs::PointCloud2::ConstPtr& reference);
  void SubscribeRigs(uint32_t queue);
  void OnPointsSeen(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void ExpirePending(const ros::WallTimerEvent&);
  void Publish(const RegistrarResult& result, const ros::Time& stamp, double total_ms);
  // The outline's alignment on aar/outline_pose and its counts for /diagnostics.
  void PublishOutline(const RegistrarResult& result, const ros::Time& stamp);
  void PublishModels();
  // Shells the static reference once the cameras' tf is there (waiting up to `tf_wait` [s]):
  // true when built. Until then the frames have no estimate and a timer tries again.
  bool TryBuildStaticReference(double tf_wait);
  // The reason a cloud's stamp is refused (empty if it is not).
  std::string StampProblem(const ros::Time& stamp) const;
  // A frame gathered without some rigs' clouds (they did not come within rig_wait): counted per
  // rig (/diagnostics) and named in a warning.
  void CountMissingRigs(const Input& input);
  void ReportError(const std::string& what);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  RegistrationNodeOptions options_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Publisher pose_pub_, estimate_pub_, models_pub_, outline_pub_;
  std::unique_ptr<OutlineInputs> outline_;                     // registrar.outline.enabled
  std::vector<std::unique_ptr<OutlineInputs>> more_outlines_;  // further rigs'
  ros::Subscriber cloud_sub_;
  using Sync =
      message_filters::TimeSynchronizer<sensor_msgs::PointCloud2, sensor_msgs::PointCloud2>;
  message_filters::Subscriber<sensor_msgs::PointCloud2> points_filter_, reference_filter_;
  std::unique_ptr<Sync> sync_;
  // Further rigs (rigs beyond the first): their clouds and references, paired by stamp.
  struct RigInputs {
    message_filters::Subscriber<sensor_msgs::PointCloud2> points, reference;
    std::unique_ptr<Sync> sync;
  };
  std::vector<std::unique_ptr<RigInputs>> rig_inputs_;
  std::unique_ptr<RigGather> gather_;  // more than one rig; under pending_mutex_
  std::vector<size_t> rig_missing_;    // frames registered without each rig's cloud
  ros::WallTimer pending_timer_;
  ros::WallTimer reference_timer_;  // retries TryBuildStaticReference
  ros::WallTime reference_wait_since_;
  aar_geometry::TriangleMesh receiver_mesh_;  // for the static reference and the outline
  std::mutex pending_mutex_;
  std::map<ros::Time, ros::WallTime> pending_;  // clouds waiting for their reference
  std::set<ros::Time> answered_;                // recent stamps already answered

  std::mutex mutex_;  // the registrar
  Registrar registrar_;
  aar_ros_common::ErrorThrottle errors_;
  aar_ros_common::StampOrder order_;  // clouds are registered in stamp order

  diagnostic_updater::Updater diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::mutex report_mutex_;  // what diagnostics read
  size_t frames_ = 0;
  std::map<TrackOutcome, size_t> outcomes_;  // tracking: frames by outcome
  std::string last_error_, last_track_reason_;
  size_t integrity_alerts_ = 0;  // poses published in alert (docs/INTEGRITY.md)
  std::string last_integrity_reason_;
  // The outline: frames it ran on, fused, and its last note and fit.
  size_t outline_ran_ = 0, outline_fused_ = 0, outline_missing_ = 0;
  std::string last_outline_note_, last_outline_missing_;
  double last_outline_quality_ = 0.0;
  TrackOutcome last_outcome_ = TrackOutcome::kMissed;
  // Every cloud taken in: an estimate or dropped, why; the one count of estimates and drops.
  aar_ros_common::FrameLedger ledger_;

  // Last: the registering thread (newest_wins; stopped first in the destructor) uses the members
  // above.
  std::unique_ptr<aar_ros_common::Stage<Input>> stage_;
};

}  // namespace aar_registration
