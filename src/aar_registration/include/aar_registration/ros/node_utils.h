#pragma once

#include <cctype>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <tf2_ros/buffer.h>

namespace aar_registration {

// Reads a node's ~parameters with their defaults and refuses keys it never read (a misspelt
// key would otherwise be silently ignored).
class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& private_nh) : nh_(private_nh) {}

  // Throws std::invalid_argument naming the parameter when it has the wrong type.
  template <typename T>
  T Get(const std::string& name, const T& fallback) {
    known_.insert(name);
    T value = fallback;
    if (nh_.hasParam(name) && !nh_.getParam(name, value))
      throw std::invalid_argument("parameter " + nh_.resolveName(name) + " has the wrong type");
    return value;
  }

  // Throws std::invalid_argument naming the first parameter Get was never asked for.
  void RejectUnknown() const {
    std::vector<std::string> names;
    nh_.getParamNames(names);
    const std::string prefix = nh_.getNamespace() + "/";
    for (const auto& name : names) {
      if (name.rfind(prefix, 0) == 0 && !known_.count(name.substr(prefix.size())))
        throw std::invalid_argument("unknown parameter " + name + " (misspelt?)");
    }
  }

 private:
  const ros::NodeHandle& nh_;
  std::set<std::string> known_;
};

// Says whether to log an error now: each kind of error (its text without digits, which vary
// from frame to frame) at most once per period of wall time. ROS's _THROTTLE macros throttle
// per call site and would hide a second, different error. Thread-safe.
class ErrorThrottle {
 public:
  explicit ErrorThrottle(double period_s = 5.0) : period_(period_s) {}

  bool ShouldLog(const std::string& what) {
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

 private:
  ros::WallDuration period_;
  std::mutex mutex_;
  std::map<std::string, ros::WallTime> last_;
};

// Waits for a transform in wall-clock time. tf2's own timed wait counts simulated time, which
// stands still in lockstep while the simulator waits for the pipeline.
inline bool WaitForTransform(const tf2_ros::Buffer& buffer, const std::string& target,
                             const std::string& source, const ros::Time& time, double timeout_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!buffer.canTransform(target, source, time)) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return false;
    ros::WallDuration(0.005).sleep();
  }
  return true;
}

}  // namespace aar_registration
