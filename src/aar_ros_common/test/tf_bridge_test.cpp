#include "aar_ros_common/tf_bridge.h"

#include <gtest/gtest.h>

#include <geometry_msgs/TransformStamped.h>

namespace aar_ros_common {
namespace {

geometry_msgs::TransformStamped Boom(double stamp, double x) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = "tanker";
  t.header.stamp = ros::Time(stamp);
  t.child_frame_id = "boom";
  t.transform.translation.x = x;
  t.transform.rotation.w = 1.0;
  return t;
}

// The boom's tf at the data's stamp has not come: without a fallback age there is no transform
// (and the error says which); with one, the latest at most that much older.
TEST(TfBridge, LookupOrLatestFallsBackOnlyWithinItsAge) {
  tf2_ros::Buffer buffer;
  buffer.setTransform(Boom(1.0, 2.0), "test");
  buffer.setTransform(Boom(1.0333, 2.5), "test");
  const ros::Time stamp(1.0666);
  std::string error;
  EXPECT_FALSE(
      LookupTransformOrLatest(buffer, "tanker", "boom", stamp, 0.0, 0.0, "the stamp", &error));
  EXPECT_NE(error.find("boom"), std::string::npos) << error;
  const auto latest =
      LookupTransformOrLatest(buffer, "tanker", "boom", stamp, 0.0, 0.1, "the stamp", &error);
  ASSERT_TRUE(latest);
  EXPECT_DOUBLE_EQ(latest->translation().x(), 2.5);
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_FALSE(
      LookupTransformOrLatest(buffer, "tanker", "boom", stamp, 0.0, 0.02, "the stamp", &error));
  // At a stamp tf has, the exact (interpolated) transform, fallback or not.
  const auto exact = LookupTransformOrLatest(buffer, "tanker", "boom", ros::Time(1.01665), 0.0, 0.1,
                                             "the stamp", &error);
  ASSERT_TRUE(exact);
  EXPECT_NEAR(exact->translation().x(), 2.25, 1e-6);
}

}  // namespace
}  // namespace aar_ros_common
