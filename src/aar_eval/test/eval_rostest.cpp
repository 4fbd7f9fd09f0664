#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <thread>

#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <aar_ros_common/rostest_main.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "aar_eval/tables.h"

TEST(Eval, FrameWithoutEstimateIsAMissNotACrash) {
  ros::NodeHandle nh;
  ros::Publisher frames = nh.advertise<sensor_msgs::CameraInfo>("/stereo/left/camera_info", 10);
  ros::Publisher estimates = nh.advertise<aar_msgs::PoseEstimate>("/aar/pose_estimate", 10);
  int errors = 0;
  ros::Subscriber error_sub = nh.subscribe<aar_msgs::PoseError>(
      "/aar/pose_error", 10, [&](const aar_msgs::PoseError::ConstPtr&) { ++errors; });
  tf2_ros::StaticTransformBroadcaster tf;
  geometry_msgs::TransformStamped truth;  // receiver 36 m aft and below: region C
  truth.header.frame_id = "tanker";
  truth.child_frame_id = "receiver_truth";
  truth.transform.translation.x = -34.5;
  truth.transform.translation.z = -10.0;
  truth.transform.rotation.w = 1.0;
  tf.sendTransform(truth);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  while (ros::WallTime::now() < deadline &&
         (frames.getNumSubscribers() == 0 || estimates.getNumSubscribers() == 0)) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(frames.getNumSubscribers(), 0u);
  ros::WallDuration(1.0).sleep();  // the truth transform reaches eval

  // Frames at 2..7 s; estimates for all but frame 4 (0.1 m off in x). Frames older than the
  // second-to-last settle: 2, 3, 4, 5.
  for (int k = 2; k <= 7; ++k) {
    sensor_msgs::CameraInfo info;
    info.header.stamp = ros::Time(k);
    frames.publish(info);
    ros::WallDuration(0.1).sleep();
    if (k != 4) {
      aar_msgs::PoseEstimate e;
      e.header.stamp = info.header.stamp;
      e.header.frame_id = "tanker";
      e.pose.position.x = -34.4;
      e.pose.position.z = -10.0;
      e.pose.orientation.w = 1.0;
      e.converged = true;
      e.valid = true;
      estimates.publish(e);
    }
    ros::WallDuration(0.2).sleep();
  }
  ros::WallDuration(1.0).sleep();
  const auto records = aar_eval::ReadFrameCsv("/tmp/aar_eval_rostest/frames.csv");
  ASSERT_EQ(records.size(), 4u);
  EXPECT_TRUE(records[0].estimated);
  EXPECT_FALSE(records[2].estimated) << "frame 4 had no estimate";
  EXPECT_NEAR(records[0].t, 1.0, 1e-9);  // stamp 2 s minus the 1 s stamp offset
  EXPECT_NEAR(records[0].error[0], 0.1,
              1e-9);  // estimate minus truth along the receiver's x: -34.4 - -34.5
  EXPECT_EQ(records[0].region, aar_geometry::Region::kC);
  EXPECT_EQ(errors, 3);
}

// Frames still waiting when eval stops settle then; those without truth were once left out
// with their log line dropped (rosconsole is gone by then): neither a row nor a word. A second
// eval, its truth frame nowhere, gets 4 frames and is stopped: each frame is named.
TEST(Eval, FramesWithoutTruthAreNamedUpToTheLast) {
  ros::NodeHandle nh;
  ros::Publisher frames = nh.advertise<sensor_msgs::CameraInfo>("/stereo/left/camera_info", 10);
  const std::string log = "/tmp/aar_eval_rostest_no_truth.log";
  std::thread eval([&] {
    std::system(("timeout --signal=INT 8 rosrun aar_eval eval_node __name:=eval_no_truth "
                 "_output_dir:=/tmp/aar_eval_rostest_no_truth _truth_frame:=nowhere > " +
                 log + " 2>&1")
                    .c_str());
  });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(6.0);
  while (ros::WallTime::now() < deadline && frames.getNumSubscribers() < 2)
    ros::WallDuration(0.05).sleep();
  ASSERT_EQ(frames.getNumSubscribers(), 2u) << "the second eval did not start";
  for (int k = 20; k <= 23; ++k) {
    sensor_msgs::CameraInfo info;
    info.header.stamp = ros::Time(k);
    frames.publish(info);
    ros::WallDuration(0.1).sleep();
  }
  eval.join();
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (int k = 20; k <= 23; ++k) {
    EXPECT_NE(text.find("no truth for frame " + std::to_string(k) + ".000000000"),
              std::string::npos)
        << "frame " << k << " not named:\n"
        << text;
  }
}

int main(int argc, char** argv) {
  return aar_ros_common::RunRostests(argc, argv, "aar_eval_rostest");
}
