#pragma once

#include <cstdint>

#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <ros/time.h>

#include "aar_eval/evaluator.h"

namespace aar_eval {

inline int64_t ToNs(const ros::Time& stamp) { return static_cast<int64_t>(stamp.toNSec()); }
inline ros::Time ToRosTime(int64_t stamp_ns) {
  ros::Time t;
  t.fromNSec(static_cast<uint64_t>(stamp_ns));
  return t;
}

Estimate ToEstimate(const aar_msgs::PoseEstimate& msg);

// The error of an estimated frame, with the estimate's header.
aar_msgs::PoseError ToPoseErrorMsg(const FrameRecord& frame, const std_msgs::Header& header);

}  // namespace aar_eval
