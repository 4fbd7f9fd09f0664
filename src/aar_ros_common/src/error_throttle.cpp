#include "aar_ros_common/error_throttle.h"

#include <cctype>

namespace aar_ros_common {

bool ErrorThrottle::ShouldLog(const std::string& what) {
  std::string key;
  for (const char c : what) {
    if (!std::isdigit(static_cast<unsigned char>(c))) key += c;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  ros::WallTime& last = last_[key];
  if (!last.isZero() && now - last <= period_) return false;
  last = now;
  return true;
}

}  // namespace aar_ros_common
