// More than one stereo rig (issue 44): a frame's clouds gathered by stamp, and the union of the
// rigs' references.
#include <gtest/gtest.h>

#include <boost/make_shared.hpp>

#include "aar_registration/ros/conversions.h"
#include "aar_registration/ros/rig_gather.h"

namespace aar_registration {
namespace {

RigGather::Cloud CloudAt(double stamp_s) {
  auto points = boost::make_shared<sensor_msgs::PointCloud2>();
  points->header.stamp = ros::Time(stamp_s);
  return {points, boost::make_shared<sensor_msgs::PointCloud2>()};
}

TEST(RigGather, AFrameIsHandedOnWhenEveryRigsCloudHasCome) {
  RigGather gather(2);
  const ros::WallTime now(100.0);
  EXPECT_TRUE(gather.Add(1, ros::Time(5.0), CloudAt(5.0), now).empty());  // the second rig first
  EXPECT_TRUE(gather.Add(1, ros::Time(5.1), CloudAt(5.1), now).empty());  // the next frame's
  EXPECT_TRUE(gather.Holds(ros::Time(5.0)));
  const auto frames = gather.Add(0, ros::Time(5.0), CloudAt(5.0), now);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].first, ros::Time(5.0));
  ASSERT_EQ(frames[0].second.size(), 2u);
  EXPECT_TRUE(frames[0].second[0].points && frames[0].second[1].points);
  EXPECT_FALSE(gather.Holds(ros::Time(5.0)));
  EXPECT_EQ(gather.held(), 1u);
  // A rig index beyond the rigs is refused, not held.
  EXPECT_TRUE(gather.Add(2, ros::Time(6.0), CloudAt(6.0), now).empty());
  EXPECT_FALSE(gather.Holds(ros::Time(6.0)));
}

// Real time: a frame completes while an older one still waits for a rig. The older one is handed
// on first, as it is: its late cloud would come after the newer frame, out of order.
TEST(RigGather, ANewerFrameCompletingHandsOnTheOlderFirst) {
  RigGather gather(2);
  const ros::WallTime now(100.0);
  EXPECT_TRUE(gather.Add(0, ros::Time(1.0), CloudAt(1.0), now).empty());
  EXPECT_TRUE(gather.Add(0, ros::Time(2.0), CloudAt(2.0), now).empty());
  EXPECT_TRUE(gather.Add(0, ros::Time(3.0), CloudAt(3.0), now).empty());
  const auto frames = gather.Add(1, ros::Time(2.0), CloudAt(2.0), now);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].first, ros::Time(1.0));
  EXPECT_FALSE(frames[0].second[1].points);  // without the second rig's
  EXPECT_EQ(frames[1].first, ros::Time(2.0));
  EXPECT_TRUE(frames[1].second[1].points);
  EXPECT_TRUE(gather.Holds(ros::Time(3.0)));  // the newer one still waits
  EXPECT_EQ(gather.held(), 1u);
}

TEST(RigGather, AFrameWhoseRigDoesNotComeIsHandedOnAfterTheWait) {
  RigGather gather(3);
  EXPECT_TRUE(gather.Add(0, ros::Time(1.0), CloudAt(1.0), ros::WallTime(10.0)).empty());
  EXPECT_TRUE(gather.Add(2, ros::Time(1.0), CloudAt(1.0), ros::WallTime(10.2)).empty());
  EXPECT_TRUE(gather.Add(0, ros::Time(2.0), CloudAt(2.0), ros::WallTime(10.4)).empty());
  EXPECT_TRUE(gather.Expire(ros::WallTime(10.5), 0.5).empty());  // from its first cloud: 0.5 s
  const auto expired = gather.Expire(ros::WallTime(10.6), 0.5);
  ASSERT_EQ(expired.size(), 1u);
  EXPECT_EQ(expired[0].first, ros::Time(1.0));
  ASSERT_EQ(expired[0].second.size(), 3u);
  EXPECT_TRUE(expired[0].second[0].points);
  EXPECT_FALSE(expired[0].second[1].points);  // missing
  EXPECT_TRUE(expired[0].second[2].points);
  EXPECT_TRUE(gather.Holds(ros::Time(2.0)));
  EXPECT_TRUE(gather.Take(ros::Time(2.0)));
  EXPECT_EQ(gather.held(), 0u);
}

TEST(MergeReferences, TheUnionKeepsEachSampleOnce) {
  const Eigen::Vector3d a(1, 0, 0), b(0, 1, 0), c(0, 0, 1), n(0, 0, 1);
  ReferencePoints first{{a, b}, {n, n}}, second{{b, c}, {n, -n}};
  const ReferencePoints merged = MergeReferences({first, second});
  ASSERT_EQ(merged.points.size(), 3u);
  EXPECT_EQ(merged.points[2], c);
  ASSERT_EQ(merged.normals.size(), 3u);
  EXPECT_EQ(merged.normals[2], -n);
  // A rig that sees nothing adds nothing; one without normals leaves the union without any (a
  // point-to-plane target needs one per point).
  EXPECT_EQ(MergeReferences({ReferencePoints{}, second}).points.size(), 2u);
  const ReferencePoints bare = MergeReferences({first, ReferencePoints{{c}, {}}});
  EXPECT_EQ(bare.points.size(), 3u);
  EXPECT_TRUE(bare.normals.empty());
}

}  // namespace
}  // namespace aar_registration
