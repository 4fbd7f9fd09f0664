#include "aar_ros_common/estimate_listener.h"

#include <cmath>

#include <aar_geometry/pose.h>
#include <tf2_eigen/tf2_eigen.h>

namespace aar_ros_common {

namespace {

bool Finite(const aar_msgs::PoseEstimate& m) {
  const auto& p = m.pose.position;
  const auto& q = m.pose.orientation;
  const auto& v = m.velocity.linear;
  const auto& w = m.velocity.angular;
  for (double x : {p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z})
    if (!std::isfinite(x)) return false;
  return std::abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1.0) < 1e-3;
}

}  // namespace

EstimateListener::EstimateListener(const ros::NodeHandle& nh, const std::string& topic,
                                   const std::string& tanker_frame)
    : tanker_frame_(tanker_frame) {
  ros::NodeHandle own(nh);
  own.setCallbackQueue(&queue_);
  sub_ = own.subscribe(topic, 10, &EstimateListener::OnEstimate, this);
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

EstimateListener::~EstimateListener() {
  spinner_->stop();
  sub_.shutdown();
  arrived_.notify_all();
}

void EstimateListener::OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& msg) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->header.stamp < last_stamp_) latest_valid_.reset();  // a bag loop: start afresh
    last_stamp_ = msg->header.stamp;
    latest_had_pose_ = msg->valid;
    track_ended_ = msg->track == aar_msgs::PoseEstimate::TRACK_LOST ||
                   msg->track == aar_msgs::PoseEstimate::TRACK_RESET;
    if (msg->valid && msg->header.frame_id != tanker_frame_) {
      if (!warned_frame_) {
        ROS_WARN_STREAM("estimates on " << sub_.getTopic() << " are in frame '"
                                        << msg->header.frame_id << "', not '" << tanker_frame_
                                        << "': not used to predict the receiver");
      }
      warned_frame_ = true;
    } else if (msg->valid && Finite(*msg)) {
      latest_valid_ = msg;
    }
  }
  arrived_.notify_all();
}

bool EstimateListener::WaitFor(const ros::Time& stamp, double timeout, bool* valid) {
  std::unique_lock<std::mutex> lock(mutex_);
  const bool arrived = arrived_.wait_for(lock, std::chrono::duration<double>(timeout), [&] {
    return last_stamp_ >= stamp || !ros::ok();
  }) && last_stamp_ >= stamp;
  if (valid) *valid = latest_had_pose_;
  return arrived;
}

std::optional<EstimateListener::Prediction> EstimateListener::Predict(const ros::Time& stamp,
                                                                      double max_age) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!latest_valid_ || track_ended_) return std::nullopt;
  const aar_msgs::PoseEstimate& m = *latest_valid_;
  const double age = (stamp - m.header.stamp).toSec();
  if (age < 0.0 || age > max_age) return std::nullopt;
  Eigen::Isometry3d T;
  tf2::fromMsg(m.pose, T);
  Eigen::Vector3d v, w;
  tf2::fromMsg(m.velocity.linear, v);
  tf2::fromMsg(m.velocity.angular, w);
  Prediction p;
  p.T_tanker_receiver = aar_geometry::ExtrapolatePose(T, v, w, age);
  p.age = age;
  p.tracking = m.track != aar_msgs::PoseEstimate::TRACK_OFF;
  return p;
}

}  // namespace aar_ros_common
