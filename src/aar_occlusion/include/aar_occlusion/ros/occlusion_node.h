#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <aar_registration/ros/node_utils.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "aar_occlusion/boom.h"
#include "aar_occlusion/dynamic_reference.h"

namespace aar_occlusion {

struct OcclusionNodeOptions {
  CullMethod cull = CullMethod::kVolumes;  // how boom points leave the sensed cloud
  BoomPartsOptions parts;                  // the cull and silhouette margins
  BoomOcclusionOptions boom;               // cull_behind_boom: the thesis's whole-ray test
  bool publish_reference = true;           // the dynamic reference model on aar/reference_cloud
  std::string robot_description = "robot_description";  // parameter holding the boom's URDF
  std::string receiver_mesh;                            // default: aar_sim's models/receiver.obj
  // 127 samples per m^2 (about 9 cm apart, 20k samples): as accurate as 400 on the default
  // approach (docs/RESULTS.md) at a third of the cost (docs/PERFORMANCE.md).
  aar_registration::ReferenceModelOptions sampling = [] {
    aar_registration::ReferenceModelOptions o;
    o.points_per_m2 = 127.0;
    return o;
  }();
  DynamicReferenceOptions reference;
  std::string tanker_frame = "tanker";
  std::string receiver_frame = "receiver";  // the latest estimate: tf tanker -> receiver
  std::string left_camera_frame = "stereo_left_optical";
  std::string right_camera_frame = "stereo_right_optical";
  double tf_timeout = 0.5;        // [s wall] waiting for the cloud's, cameras' and links' tf
  double estimate_max_age = 1.0;  // [s] an older estimate is not used as the predicted pose
  // [s wall] how long to wait for the estimate of the previous cloud (tf tanker -> receiver at
  // its stamp): in lockstep it is on its way, and waiting makes runs repeatable.
  double estimate_wait = 0.2;
  double diagnostic_period = 1.0;  // [s wall] /diagnostics
  double marker_length = 30.0;     // [m] how far the shadow-volume markers reach past the boom
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
OcclusionNodeOptions LoadOcclusionNodeOptions(const ros::NodeHandle& private_nh);

// Per sensed cloud (~points): the boom's volumes from tf (rebuilt when a link or camera moves),
// the cloud without boom points (aar/points_filtered, aar/boom_points), the dynamic reference
// model at the predicted pose (aar/reference_cloud) and the shadow volumes (aar/shadow_volumes).
// When the boom cannot be placed (bad model, missing tf), clouds pass through unculled, the
// reference accounts for self-occlusion only, and diagnostics say why.
class OcclusionNode {
 public:
  OcclusionNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                const OcclusionNodeOptions& options);
  ~OcclusionNode();

 private:
  void OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  std::optional<Eigen::Isometry3d> Lookup(const std::string& frame, const ros::Time& stamp,
                                          std::string* error);
  void PublishMarkers(const std_msgs::Header& header);
  void ReportError(const std::string& what);
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  OcclusionNodeOptions options_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  ros::Publisher filtered_pub_, boom_pub_, reference_pub_, markers_pub_;
  ros::Subscriber cloud_sub_;
  diagnostic_updater::Updater diagnostics_;
  ros::WallTimer diagnostics_timer_;

  std::mutex mutex_;
  std::unique_ptr<BoomOcclusion> boom_;  // null when the boom model was refused
  std::string boom_error_;               // why, naming the link
  std::unique_ptr<DynamicReference> reference_;
  bool markers_stale_ = true;

  aar_registration::ErrorThrottle errors_;
  std::mutex report_mutex_;                  // guards what diagnostics read
  std::string last_frame_error_;             // empty when the last frame was culled as configured
  std::string last_reference_error_;         // empty when the last reference was built
  std::optional<ros::Time> previous_stamp_;  // of the previous cloud
  uint64_t frames_ = 0, unculled_frames_ = 0, reference_failures_ = 0;
  double last_ms_ = 0.0;
  size_t last_boom_points_ = 0, last_reference_both_ = 0;
};

}  // namespace aar_occlusion
