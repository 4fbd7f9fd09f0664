#pragma once

#include <map>
#include <mutex>
#include <string>

#include <ros/time.h>

namespace aar_ros_common {

// Says whether to log an error now: each kind of error (its text without digits, which vary
// from frame to frame) at most once per period of wall time. ROS's _THROTTLE macros throttle
// per call site and would hide a second, different error. Thread-safe.
class ErrorThrottle {
 public:
  explicit ErrorThrottle(double period_s = 5.0) : period_(period_s) {}

  bool ShouldLog(const std::string& what);

 private:
  ros::WallDuration period_;
  std::mutex mutex_;
  std::map<std::string, ros::WallTime> last_;
};

}  // namespace aar_ros_common
