#include "aar_testing/logged_errors.h"

#include <rosgraph_msgs/Log.h>

#include "aar_testing/wait.h"

namespace aar_testing {

LoggedErrors::LoggedErrors(ros::NodeHandle& nh, const std::string& node, uint8_t min_level) {
  static_assert(rosgraph_msgs::Log::ERROR == 8, "the header's default level is ERROR");
  sub_ = nh.subscribe<rosgraph_msgs::Log>(
      "/rosout", 100, [this, node, min_level](const rosgraph_msgs::Log::ConstPtr& m) {
        if (m->level < min_level || m->name != node) return;
        std::lock_guard<std::mutex> lock(mutex_);
        errors_.push_back(m->msg);
      });
}

bool LoggedErrors::Wait(const std::string& text, double timeout_s) {
  return !WaitMessage(text, timeout_s).empty();
}

std::string LoggedErrors::WaitMessage(const std::string& text, double timeout_s) {
  std::string found;
  WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& e : errors_) {
          if (e.find(text) != std::string::npos) {
            found = e;
            return true;
          }
        }
        return false;
      },
      timeout_s);
  return found;
}

}  // namespace aar_testing
