#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <aar_description/boom_parts.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>

#include "aar_registration/registrar.h"

namespace aar_registration {

// What the outline needs each frame, gathered on the ROS side: the rectified pair and its camera
// infos (left/image_rect, left/camera_info, right/image_rect, right/camera_info, paired by stamp
// and kept for the last few stamps), the cameras' and the boom links' poses from tf at the stamp,
// and the boom's convex parts from the URDF in parameter `robot_description`, looked up from `nh`
// and searched up (aar_ros_common::LoadRobotDescription; empty: the tanker flies no boom; no boom
// model: nothing is masked, said once).
class OutlineInputs {
 public:
  // `topic_prefix`: a further rig's (R/: R/left/image_rect, ...; issue 44), whose frames carry
  // no boom parts (the first rig's frame has them): robot_description unused.
  OutlineInputs(ros::NodeHandle nh, const tf2_ros::Buffer& tf, const std::string& tanker_frame,
                const std::string& robot_description, double tf_timeout, double tf_fallback_age,
                const std::string& topic_prefix = "");
  ~OutlineInputs();

  // The frame at `stamp`; nullopt with the reason when its images have not come (or are not
  // mono8 of their camera's size) or tf lacks a camera.
  std::optional<OutlineFrame> Get(const ros::Time& stamp, std::string* error);

  size_t pairs_received() const { return pairs_; }
  const std::string& boom_error() const { return boom_error_; }

 private:
  struct Pair {
    sensor_msgs::Image::ConstPtr left, right;
    sensor_msgs::CameraInfo::ConstPtr left_info, right_info;
  };
  void OnPair(const sensor_msgs::Image::ConstPtr& left,
              const sensor_msgs::CameraInfo::ConstPtr& left_info,
              const sensor_msgs::Image::ConstPtr& right,
              const sensor_msgs::CameraInfo::ConstPtr& right_info);
  std::optional<aar_alignment::PinholeCamera> Camera(const sensor_msgs::CameraInfo& info,
                                                     const ros::Time& stamp,
                                                     std::string* error) const;

  const tf2_ros::Buffer& tf_;
  std::string tanker_frame_;
  double tf_timeout_;
  double tf_fallback_age_;  // [s] the boom links' latest tf when the images' has not come
  message_filters::Subscriber<sensor_msgs::Image> left_sub_, right_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> left_info_sub_, right_info_sub_;
  using Sync = message_filters::TimeSynchronizer<sensor_msgs::Image, sensor_msgs::CameraInfo,
                                                 sensor_msgs::Image, sensor_msgs::CameraInfo>;
  std::unique_ptr<Sync> sync_;
  std::mutex mutex_;
  std::map<ros::Time, Pair> pairs_by_stamp_;  // the last kKeptPairs
  size_t pairs_ = 0;
  std::vector<aar_description::BoomCollisionPart> boom_;
  std::vector<std::string> boom_links_;
  std::string boom_error_;
};

}  // namespace aar_registration
