#pragma once

#include <map>
#include <mutex>
#include <string>

#include <ros/ros.h>

namespace aar_testing {

// For rostests: keeps the latest message of each stamp on a topic (needs a spinner running).
// Lock `mutex` to read `by_stamp`.
template <typename Msg>
struct StampedCollector {
  std::mutex mutex;
  std::map<ros::Time, boost::shared_ptr<const Msg>> by_stamp;
  ros::Subscriber sub;

  StampedCollector(ros::NodeHandle& nh, const std::string& topic, uint32_t queue = 20) {
    sub = nh.subscribe<Msg>(topic, queue, [this](const boost::shared_ptr<const Msg>& m) {
      std::lock_guard<std::mutex> lock(mutex);
      by_stamp[m->header.stamp] = m;
    });
  }
  size_t size() {
    std::lock_guard<std::mutex> lock(mutex);
    return by_stamp.size();
  }
};

}  // namespace aar_testing
