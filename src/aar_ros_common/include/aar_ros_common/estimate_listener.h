#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <aar_msgs/PoseEstimate.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <Eigen/Geometry>

namespace aar_ros_common {

// The receiver pose predicted at a new stamp from the latest aar_msgs/PoseEstimate: its pose moved
// on by its velocity (zero without tracking), so that stages ahead of registration (stereo's
// region of interest, the occlusion stage's reference model) can place the receiver before this
// frame is registered. Listens on a thread of its own, so a stage may wait inside its callback for
// the estimate of the previous frame (repeatable lockstep runs).
class EstimateListener {
 public:
  struct Prediction {
    Eigen::Isometry3d T_tanker_receiver;  // at the stamp asked for
    double age = 0.0;                     // [s] from the estimate's stamp to the stamp asked for
    bool tracking = false;                // the estimate came from a live track (started,
                                          // accepted or coasting), not a lone registration
  };

  // `tanker_frame`: estimates in another frame are ignored (and named once in a warning).
  EstimateListener(const ros::NodeHandle& nh, const std::string& topic,
                   const std::string& tanker_frame);
  ~EstimateListener();

  // Blocks up to `timeout` [s wall] until an estimate stamped `stamp` or later has arrived. With
  // `valid`, also says whether the latest estimate had a pose (registration sends the receiver's
  // tf only then, so a stage waiting for that tf need not wait after a miss).
  bool WaitFor(const ros::Time& stamp, double timeout, bool* valid = nullptr);

  // The latest valid estimate moved on to `stamp`, if it is at most `max_age` [s] older than
  // `stamp` and not newer (a bag loop), and the latest estimate did not end its track (lost or
  // reset). Never NaN: an estimate with a non-finite pose or velocity is not kept.
  std::optional<Prediction> Predict(const ros::Time& stamp, double max_age) const;

 private:
  void OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& msg);

  std::string tanker_frame_;
  ros::CallbackQueue queue_;
  ros::Subscriber sub_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  ros::Time last_stamp_;                           // of any estimate
  aar_msgs::PoseEstimate::ConstPtr latest_valid_;  // the latest with a usable pose
  bool track_ended_ = false;                       // the latest estimate said lost or reset
  bool latest_had_pose_ = false;                   // the latest estimate was valid
  bool warned_frame_ = false;
};

}  // namespace aar_ros_common
