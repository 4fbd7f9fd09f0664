#include "aar_ros_common/frame_ledger.h"

#include <aar_msgs/FrameOutcome.h>

namespace aar_ros_common {

FrameLedger::FrameLedger(ros::NodeHandle nh, const std::string& stage, const std::string& rig)
    : stage_(rig.empty() ? stage : rig + "/" + stage) {
  // Small messages, one per frame and stage: a long queue, so that none is dropped unseen.
  pub_ = nh.advertise<aar_msgs::FrameOutcome>(kFrameOutcomeTopic, 100);
}

void FrameLedger::Passed(const ros::Time& stamp) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++passed_;
  }
  Publish(stamp, aar_msgs::FrameOutcome::PASSED, "", "");
}

uint64_t FrameLedger::Dropped(const ros::Time& stamp, const std::string& reason,
                              const std::string& detail) {
  uint64_t count = 1;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = dropped_.begin();
    while (it != dropped_.end() && it->first != reason) ++it;
    if (it == dropped_.end())
      dropped_.emplace_back(reason, 1);
    else
      count = ++it->second;
  }
  Publish(stamp, aar_msgs::FrameOutcome::DROPPED, reason, detail);
  return count;
}

void FrameLedger::Publish(const ros::Time& stamp, uint8_t outcome, const std::string& reason,
                          const std::string& detail) {
  aar_msgs::FrameOutcome msg;
  msg.header.stamp = stamp;
  msg.stage = stage_;
  msg.outcome = outcome;
  msg.reason = reason;
  msg.detail = detail;
  pub_.publish(msg);
}

std::vector<std::pair<std::string, uint64_t>> FrameLedger::Counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<std::string, uint64_t>> counts{{"frames passed", passed_}};
  for (const auto& [reason, n] : dropped_) counts.emplace_back("frames dropped: " + reason, n);
  return counts;
}

}  // namespace aar_ros_common
