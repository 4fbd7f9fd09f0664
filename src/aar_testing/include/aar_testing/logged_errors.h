#pragma once

#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>

namespace aar_testing {

// For rostests: the ERROR and FATAL messages (or from `min_level` up, e.g. WARN) that one node
// logs to /rosout (needs a spinner running), so a test can check that bad input is named.
class LoggedErrors {
 public:
  // `node`: the logger's full name, e.g. "/registration".
  LoggedErrors(ros::NodeHandle& nh, const std::string& node, uint8_t min_level = 8);  // 8: ERROR

  // True once an error containing `text` was logged, within `timeout_s` [s wall].
  bool Wait(const std::string& text, double timeout_s);
  // The first message containing `text`, waiting up to `timeout_s` [s wall]; empty if none came.
  std::string WaitMessage(const std::string& text, double timeout_s);
  // True once /rosout has a publisher (the node's logs can arrive).
  bool Connected() const { return sub_.getNumPublishers() > 0; }

 private:
  std::mutex mutex_;
  std::vector<std::string> errors_;
  ros::Subscriber sub_;
};

}  // namespace aar_testing
