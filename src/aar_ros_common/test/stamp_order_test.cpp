#include <gtest/gtest.h>

#include "aar_ros_common/stamp_order.h"

namespace aar_ros_common {
namespace {

TEST(StampOrder, LateAndRepeatedStampsAreOutOfOrderUnlessTheClockWentBack) {
  StampOrder order;
  const ros::Time clock(1000.0);
  EXPECT_EQ(order.Check(ros::Time(10.0), clock), "");
  EXPECT_EQ(order.Check(ros::Time(10.1), clock + ros::Duration(0.1)), "");
  // Late: both stamps named.
  EXPECT_EQ(order.Check(ros::Time(10.05), clock + ros::Duration(0.2)),
            "stamp 10.050000000 is 0.050 s before the last one taken, 10.100000000: out of order");
  EXPECT_EQ(order.Check(ros::Time(10.1), clock + ros::Duration(0.2)),
            "stamp 10.100000000 repeats the last one taken: out of order");
  EXPECT_EQ(order.dropped(), 2u);
  // The late ones did not move the last stamp: the next in order is taken.
  EXPECT_EQ(order.Check(ros::Time(10.2), clock + ros::Duration(0.3)), "");
  // A bag that loops: the clock goes back with the stamps, and time starts again.
  EXPECT_EQ(order.Check(ros::Time(1.0), ros::Time(1.0)), "");
  EXPECT_EQ(order.Check(ros::Time(1.1), ros::Time(1.1)), "");
  EXPECT_NE(order.Check(ros::Time(1.0), ros::Time(1.1)), "");
}

}  // namespace
}  // namespace aar_ros_common
