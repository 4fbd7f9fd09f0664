#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "aar_registration/icp.h"
#include "aar_registration/reference_model.h"
#include "aar_registration/ros/node_utils.h"

namespace aar_registration {

enum class ReferenceKind { kShelled, kWingsNose, kDense, kTopic };
enum class SeedMode { kCentroid, kPrevious };

struct RegistrationNodeOptions {
  ReferenceKind reference = ReferenceKind::kShelled;  // static model, or /aar/reference_cloud
  std::string receiver_mesh;                          // default: aar_sim's models/receiver.obj
  ReferenceModelOptions sampling;
  Eigen::Isometry3d T_tanker_receiver_nominal = Eigen::Isometry3d::Identity();  // shelling pose
  IcpOptions icp;
  SeedMode seed = SeedMode::kCentroid;  // thesis: centroid of the sensed points, tanker orientation
  double previous_max_age = 1.0;        // [s] older previous estimates are not used as seeds
  std::string tanker_frame = "tanker";
  std::string receiver_frame = "receiver";
  std::string truth_frame = "receiver_truth";             // only for the rviz model at truth
  std::string left_camera_frame = "stereo_left_optical";  // eyes for shelling, from tf
  std::string right_camera_frame = "stereo_right_optical";
  double tf_timeout = 0.5;  // [s wall] waiting for the sensed cloud's transform
  // [s wall] reference: topic: a cloud without a reference of its stamp this long is answered
  // with an invalid estimate.
  double reference_timeout = 2.0;
};

// Reads ~parameters (one function, unknown keys rejected); throws std::invalid_argument.
RegistrationNodeOptions LoadRegistrationNodeOptions(const ros::NodeHandle& private_nh);

// Registers each sensed cloud (~points, any frame with tf to the tanker) against the receiver's
// reference model and publishes the pose.
class RegistrationNode {
 public:
  RegistrationNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                   const RegistrationNodeOptions& options);
  ~RegistrationNode();

 private:
  void OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void Register(const sensor_msgs::PointCloud2::ConstPtr& msg);  // mutex_ held
  void OnPair(const sensor_msgs::PointCloud2::ConstPtr& points,
              const sensor_msgs::PointCloud2::ConstPtr& reference);
  void SetReference(const sensor_msgs::PointCloud2& msg);  // throws std::invalid_argument
  void OnPointsSeen(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void ExpirePending(const ros::WallTimerEvent&);
  void PublishNone(const ros::Time& stamp, double total_ms);
  void PublishModels();
  void BuildStaticReference();
  void ReportError(const std::string& what);

  ros::NodeHandle nh_;
  RegistrationNodeOptions options_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Publisher pose_pub_, estimate_pub_, models_pub_;
  ros::Subscriber cloud_sub_;
  using Sync =
      message_filters::TimeSynchronizer<sensor_msgs::PointCloud2, sensor_msgs::PointCloud2>;
  message_filters::Subscriber<sensor_msgs::PointCloud2> points_filter_, reference_filter_;
  std::unique_ptr<Sync> sync_;
  ros::WallTimer pending_timer_;
  std::mutex pending_mutex_;
  std::map<ros::Time, ros::WallTime> pending_;  // clouds waiting for their reference
  std::set<ros::Time> answered_;                // recent stamps already answered

  std::mutex mutex_;  // the target and the previous estimate
  Icp icp_;
  std::vector<Eigen::Vector3d> reference_points_;                    // in the receiver frame
  std::optional<std::pair<ros::Time, Eigen::Isometry3d>> previous_;  // T_tanker_receiver
  ErrorThrottle errors_;
};

}  // namespace aar_registration
