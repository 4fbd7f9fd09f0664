#include "aar_registration/ros/outline_inputs.h"

#include <set>

#include <aar_alignment/boom_parts.h>
#include <aar_ros_common/robot_description.h>
#include <aar_ros_common/tf_bridge.h>
#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

namespace aar_registration {
namespace {

constexpr size_t kKeptPairs = 8;

}  // namespace

OutlineInputs::OutlineInputs(ros::NodeHandle nh, const tf2_ros::Buffer& tf,
                             const std::string& tanker_frame, const std::string& robot_description,
                             double tf_timeout, double tf_fallback_age,
                             const std::string& topic_prefix)
    : tf_(tf),
      tanker_frame_(tanker_frame),
      tf_timeout_(tf_timeout),
      tf_fallback_age_(tf_fallback_age) {
  if (!topic_prefix.empty()) {
    // A further rig: the first rig's frame carries the boom.
  } else if (robot_description.empty()) {
    ROS_INFO("registration: no boom modelled (model_boom: false): the outline masks none");
  } else {
    try {
      boom_ = aar_description::LoadBoomCollisionParts(
          aar_ros_common::LoadRobotDescription(nh, robot_description));
      std::set<std::string> links;
      for (const auto& part : boom_) links.insert(part.link);
      boom_links_.assign(links.begin(), links.end());
    } catch (const std::exception& e) {
      boom_error_ = e.what();
    }
  }
  if (!boom_error_.empty())
    ROS_WARN_STREAM("registration: the outline masks no boom: " << boom_error_);
  left_sub_.subscribe(nh, topic_prefix + "left/image_rect", 2);
  left_info_sub_.subscribe(nh, topic_prefix + "left/camera_info", 2);
  right_sub_.subscribe(nh, topic_prefix + "right/image_rect", 2);
  right_info_sub_.subscribe(nh, topic_prefix + "right/camera_info", 2);
  sync_ = std::make_unique<Sync>(left_sub_, left_info_sub_, right_sub_, right_info_sub_, 10);
  sync_->registerCallback(&OutlineInputs::OnPair, this);
}

OutlineInputs::~OutlineInputs() {
  left_sub_.unsubscribe();
  left_info_sub_.unsubscribe();
  right_sub_.unsubscribe();
  right_info_sub_.unsubscribe();
}

void OutlineInputs::OnPair(const sensor_msgs::Image::ConstPtr& left,
                           const sensor_msgs::CameraInfo::ConstPtr& left_info,
                           const sensor_msgs::Image::ConstPtr& right,
                           const sensor_msgs::CameraInfo::ConstPtr& right_info) {
  std::lock_guard<std::mutex> lock(mutex_);
  pairs_by_stamp_[left->header.stamp] = Pair{left, right, left_info, right_info};
  while (pairs_by_stamp_.size() > kKeptPairs) pairs_by_stamp_.erase(pairs_by_stamp_.begin());
  ++pairs_;
}

std::optional<aar_alignment::PinholeCamera> OutlineInputs::Camera(
    const sensor_msgs::CameraInfo& info, const ros::Time& stamp, std::string* error) const {
  const auto T = aar_ros_common::LookupTransform(tf_, tanker_frame_, info.header.frame_id, stamp,
                                                 tf_timeout_, "the images' stamp", error);
  if (!T) return std::nullopt;
  aar_alignment::PinholeCamera c;
  c.width = static_cast<int>(info.width), c.height = static_cast<int>(info.height);
  // Rectified: the projection matrix P holds the intrinsics of the rectified image.
  c.fx = info.P[0], c.fy = info.P[5], c.cx = info.P[2], c.cy = info.P[6];
  c.T_tanker_optical = *T;
  if (!(c.fx > 0.0 && c.fy > 0.0)) {
    *error = "camera_info of " + info.header.frame_id + " has no projection matrix (P)";
    return std::nullopt;
  }
  return c;
}

std::optional<OutlineFrame> OutlineInputs::Get(const ros::Time& stamp, std::string* error) {
  Pair pair;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = pairs_by_stamp_.find(stamp);
    if (it == pairs_by_stamp_.end()) {
      *error =
          "no image pair of the cloud's stamp (left/image_rect, right/image_rect and their "
          "camera_info)";
      return std::nullopt;
    }
    pair = it->second;
  }
  OutlineFrame frame;
  const auto left = Camera(*pair.left_info, stamp, error);
  auto right = left ? Camera(*pair.right_info, stamp, error) : std::nullopt;
  if (!left || !right) return std::nullopt;
  // ROS's stereo convention (image_geometry::StereoCameraModel): the right P projects points of
  // the left rectified frame, its Tx = -fx B placing the right camera B along the left's x,
  // whatever frame_id the right camera_info names.
  if (pair.right_info->P[3] != 0.0) {
    right->T_tanker_optical =
        left->T_tanker_optical * Eigen::Translation3d(-pair.right_info->P[3] / right->fx, 0, 0);
  }
  frame.left_camera = *left, frame.right_camera = *right;
  try {
    frame.left = cv_bridge::toCvShare(pair.left, sensor_msgs::image_encodings::MONO8)->image;
    frame.right = cv_bridge::toCvShare(pair.right, sensor_msgs::image_encodings::MONO8)->image;
  } catch (const std::exception& e) {
    *error = std::string("images not convertible to mono8: ") + e.what();
    return std::nullopt;
  }
  std::map<std::string, Eigen::Isometry3d> links;
  for (const auto& link : boom_links_) {
    std::string missing;
    const auto T =
        aar_ros_common::LookupTransformOrLatest(tf_, tanker_frame_, link, stamp, tf_timeout_,
                                                tf_fallback_age_, "the images' stamp", &missing);
    if (!T) {  // unmasked, the boom's edges would pull the outline
      *error = "the boom cannot be masked: " + missing;
      return std::nullopt;
    }
    links[link] = *T;
  }
  frame.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(boom_, links);
  return frame;
}

}  // namespace aar_registration
