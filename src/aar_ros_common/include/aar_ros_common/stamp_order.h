#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include <ros/time.h>

namespace aar_ros_common {

// Frames are taken in stamp order. A message stamped no later than the last one taken came late
// (out of order) or again, and is to be dropped: a Kalman filter must not be fed an older stamp,
// and a late frame's result would be stale. Unless the clock went back since that one was taken
// (a bag that loops, a restarted simulator): time started again, and the message is taken.
// Thread-safe.
class StampOrder {
 public:
  // Empty: take the message, it is now the last one taken. Otherwise why it is out of order,
  // naming both stamps. `now`: the node's clock (ros::Time::now()).
  std::string Check(const ros::Time& stamp, const ros::Time& now);
  uint64_t dropped() const { return dropped_; }

 private:
  std::mutex mutex_;
  bool any_ = false;
  ros::Time last_stamp_, clock_at_last_;
  std::atomic<uint64_t> dropped_{0};
};

}  // namespace aar_ros_common
