#include "aar_testing/logged_errors.h"

#include <rosgraph_msgs/Log.h>

#include "aar_testing/wait.h"

namespace aar_testing {

LoggedErrors::LoggedErrors(ros::NodeHandle& nh, const std::string& node) {
  sub_ = nh.subscribe<rosgraph_msgs::Log>(
      "/rosout", 100, [this, node](const rosgraph_msgs::Log::ConstPtr& m) {
        if (m->level < rosgraph_msgs::Log::ERROR || m->name != node) return;
        std::lock_guard<std::mutex> lock(mutex_);
        errors_.push_back(m->msg);
      });
}

bool LoggedErrors::Wait(const std::string& text, double timeout_s) {
  return WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& e : errors_)
          if (e.find(text) != std::string::npos) return true;
        return false;
      },
      timeout_s);
}

}  // namespace aar_testing
