#include "aar_ros_common/tf_bridge.h"

#include <tf2_eigen/tf2_eigen.h>

namespace aar_ros_common {

bool WaitForTransform(const tf2_ros::Buffer& buffer, const std::string& target,
                      const std::string& source, const ros::Time& time, double timeout_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!buffer.canTransform(target, source, time)) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return false;
    ros::WallDuration(0.005).sleep();
  }
  return true;
}

std::optional<Eigen::Isometry3d> LookupTransform(const tf2_ros::Buffer& buffer,
                                                 const std::string& target,
                                                 const std::string& source, const ros::Time& time,
                                                 double timeout_s, const std::string& stamp_what,
                                                 std::string* error) {
  if (!WaitForTransform(buffer, target, source, time, timeout_s)) {
    if (error) {
      *error = "no tf " + target + " -> '" + source + "' at " + stamp_what + " within " +
               std::to_string(timeout_s) + " s";
    }
    return std::nullopt;
  }
  return tf2::transformToEigen(buffer.lookupTransform(target, source, time));
}

std::optional<Eigen::Isometry3d> LatestTransform(const tf2_ros::Buffer& buffer,
                                                 const std::string& target,
                                                 const std::string& source, const ros::Time& time,
                                                 double max_age) {
  if (!buffer.canTransform(target, source, ros::Time(0))) return std::nullopt;
  const auto latest = buffer.lookupTransform(target, source, ros::Time(0));
  const double age = (time - latest.header.stamp).toSec();
  if (age < 0.0 || age > max_age) return std::nullopt;
  return tf2::transformToEigen(latest);
}

std::optional<Eigen::Isometry3d> LookupTransformOrLatest(
    const tf2_ros::Buffer& buffer, const std::string& target, const std::string& source,
    const ros::Time& time, double timeout_s, double fallback_age, const std::string& stamp_what,
    std::string* error) {
  auto T = LookupTransform(buffer, target, source, time, timeout_s, stamp_what, error);
  if (!T && fallback_age > 0.0) {
    T = LatestTransform(buffer, target, source, time, fallback_age);
    if (T && error) error->clear();
  }
  return T;
}

}  // namespace aar_ros_common
