#include <gtest/gtest.h>

#include "aar_ros_common/error_throttle.h"

namespace aar_ros_common {
namespace {

TEST(ErrorThrottle, OncePerKindOfErrorPerPeriod) {
  ros::Time::init();
  ErrorThrottle throttle(60.0);
  EXPECT_TRUE(throttle.ShouldLog("cloud has 3 points"));
  EXPECT_FALSE(throttle.ShouldLog("cloud has 7 points"));  // same kind: only digits differ
  EXPECT_TRUE(throttle.ShouldLog("no tf tanker -> 'boom'"));
  ErrorThrottle fast(0.0);
  EXPECT_TRUE(fast.ShouldLog("x"));
  ros::WallDuration(0.001).sleep();
  EXPECT_TRUE(fast.ShouldLog("x"));
}

}  // namespace
}  // namespace aar_ros_common
