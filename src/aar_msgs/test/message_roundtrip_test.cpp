#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

namespace {

// Publishes `sent` until one copy comes back on the same topic, or 10 s pass.
template <typename Msg>
boost::shared_ptr<const Msg> RoundTrip(const std::string& topic, const Msg& sent) {
  ros::NodeHandle nh;
  boost::shared_ptr<const Msg> received;
  ros::Subscriber sub =
      nh.subscribe<Msg>(topic, 1, [&](const boost::shared_ptr<const Msg>& m) { received = m; });
  ros::Publisher pub = nh.advertise<Msg>(topic, 1);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!received && ros::WallTime::now() < deadline) {
    pub.publish(sent);
    ros::spinOnce();
    ros::WallDuration(0.05).sleep();
  }
  return received;
}

TEST(AarMsgs, PoseEstimateRoundTrip) {
  aar_msgs::PoseEstimate sent;
  sent.header.frame_id = "tanker";
  sent.header.stamp = ros::Time(12, 34);
  sent.pose.position.x = -35.25;
  sent.pose.orientation.w = 1.0;
  sent.valid = true;
  sent.converged = true;
  sent.iterations = 17;
  sent.rms = 0.0125;
  sent.fitness = 0.97;
  sent.sensed_points = 7800;
  sent.reference_points = 21000;
  sent.stereo_ms = 21.5;
  sent.occlusion_ms = 1.25;
  sent.registration_ms = 8.0;
  sent.total_ms = 31.0;
  sent.covariance[0] = 1e-4;
  sent.covariance[35] = 3e-6;
  sent.velocity.linear.x = 0.5;
  sent.seed = aar_msgs::PoseEstimate::SEED_PREDICTION;
  sent.track = aar_msgs::PoseEstimate::TRACK_REJECTED;
  sent.track_reason = "RMS 0.3 m > 0.25 m";
  const auto got = RoundTrip("/aar/pose_estimate_test", sent);
  ASSERT_TRUE(got) << "no message came back within 10 s";
  EXPECT_EQ(got->header.frame_id, "tanker");
  EXPECT_EQ(got->header.stamp, sent.header.stamp);
  EXPECT_EQ(got->pose.position.x, -35.25);
  EXPECT_TRUE(got->valid);
  EXPECT_TRUE(got->converged);
  EXPECT_EQ(got->iterations, 17u);
  EXPECT_EQ(got->reference_points, 21000u);
  EXPECT_EQ(got->covariance[0], 1e-4);
  EXPECT_EQ(got->covariance[35], 3e-6);
  EXPECT_EQ(got->velocity.linear.x, 0.5);
  EXPECT_EQ(got->seed, aar_msgs::PoseEstimate::SEED_PREDICTION);
  EXPECT_EQ(got->track, aar_msgs::PoseEstimate::TRACK_REJECTED);
  EXPECT_EQ(got->track_reason, "RMS 0.3 m > 0.25 m");
  EXPECT_EQ(got->total_ms, 31.0);
}

TEST(AarMsgs, PoseErrorRoundTrip) {
  aar_msgs::PoseError sent;
  sent.region = aar_msgs::PoseError::REGION_C;
  sent.range_m = 34.5;
  sent.x_m = 0.16;
  sent.yaw_deg = -0.44;
  const auto got = RoundTrip("/aar/pose_error_test", sent);
  ASSERT_TRUE(got) << "no message came back within 10 s";
  EXPECT_EQ(got->region, 3);
  EXPECT_EQ(got->range_m, 34.5);
  EXPECT_EQ(got->x_m, 0.16);
  EXPECT_EQ(got->yaw_deg, -0.44);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "aar_msgs_message_roundtrip_test");
  return RUN_ALL_TESTS();
}
