#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <ros/ros.h>

namespace aar_ros_common {

// The topic every stage reports its frames on (aar_msgs/FrameOutcome); absolute, remappable.
constexpr const char* kFrameOutcomeTopic = "/aar/frame_outcome";

// A stage's part of the frame ledger (docs/RELIABILITY.md, Frame ledger): every frame the stage
// takes in ends in one call, Passed (its output published) or Dropped (with a reason key from
// aar_msgs/FrameOutcome and a sentence). Each call publishes an aar_msgs/FrameOutcome and counts
// it; Counts() gives the counts for the stage's /diagnostics. Thread-safe.
class FrameLedger {
 public:
  // `rig`: the rig a stage serves when there are several (CommonNodeOptions::rig): it reports as
  // RIG/STAGE. Empty: STAGE.
  FrameLedger(ros::NodeHandle nh, const std::string& stage, const std::string& rig = "");

  void Passed(const ros::Time& stamp);
  // Returns the frames dropped for `reason` so far, this one included (for the stage's warning).
  uint64_t Dropped(const ros::Time& stamp, const std::string& reason, const std::string& detail);

  // ("frames passed", n), then ("frames dropped: REASON", n) per reason, in the order the
  // reasons first occurred; the keys are the stage's /diagnostics keys.
  std::vector<std::pair<std::string, uint64_t>> Counts() const;

 private:
  void Publish(const ros::Time& stamp, uint8_t outcome, const std::string& reason,
               const std::string& detail);

  std::string stage_;
  ros::Publisher pub_;
  mutable std::mutex mutex_;
  uint64_t passed_ = 0;
  std::vector<std::pair<std::string, uint64_t>> dropped_;  // per reason
};

}  // namespace aar_ros_common
