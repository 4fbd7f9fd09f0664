#include <gtest/gtest.h>

#include <aar_geometry/pose_error.h>
#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <aar_sim/ros/stamped_collector.h>
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>

namespace {

Eigen::Isometry3d ToEigen(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << t.translation.x, t.translation.y, t.translation.z;
  T.linear() =
      Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  return T;
}

Eigen::Isometry3d ToEigen(const geometry_msgs::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << p.position.x, p.position.y, p.position.z;
  T.linear() =
      Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)
          .toRotationMatrix();
  return T;
}

TEST(NearContact, NoBoomErrorsUnderTenCentimetresAndOneDegree) {
  ros::NodeHandle nh;
  aar_sim::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  aar_sim::StampedCollector<aar_msgs::PoseError> errors(nh, "/aar/pose_error");
  tf2_ros::Buffer tf(ros::Duration(120.0));
  tf2_ros::TransformListener listener(tf);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(200.0);
  while (ros::WallTime::now() < deadline && estimates.size() < 20) ros::WallDuration(0.1).sleep();
  ASSERT_GE(estimates.size(), 18u) << "estimates for fewer than 18 of 20 frames";

  double position = 0.0, orientation = 0.0;
  int n = 0, converged = 0, checked_errors = 0;
  std::lock_guard<std::mutex> lock(estimates.mutex);
  for (const auto& [stamp, estimate] : estimates.by_stamp) {
    const auto truth = tf.lookupTransform("tanker", "receiver_truth", stamp, ros::Duration(2.0));
    const aar_geometry::PoseError e =
        aar_geometry::ComputePoseError(ToEigen(truth.transform), ToEigen(estimate->pose));
    const double angle = aar_geometry::RadToDeg(
        Eigen::Vector3d(e.orientation_rad.roll, e.orientation_rad.pitch, e.orientation_rad.yaw)
            .norm());
    std::printf(
        "[ near contact ] %.1f s, %.1f m (region %s): error %.3f m, %.3f deg; %u points, %u "
        "iterations%s\n",
        stamp.toSec(), e.range_m, aar_geometry::RegionName(e.region).c_str(), e.position_m.norm(),
        angle, estimate->sensed_points, estimate->iterations,
        estimate->converged ? "" : ", not converged");
    // eval_node's error for the same frame agrees with this one (it settles frames one behind).
    std::lock_guard<std::mutex> error_lock(errors.mutex);
    if (errors.by_stamp.count(stamp)) {
      const aar_msgs::PoseError& m = *errors.by_stamp.at(stamp);
      EXPECT_NEAR(m.x_m, e.position_m.x(), 1e-6);
      EXPECT_NEAR(m.yaw_deg, aar_geometry::RadToDeg(e.orientation_rad.yaw), 1e-6);
      EXPECT_NEAR(m.range_m, e.range_m, 1e-6);
      EXPECT_EQ(m.region, aar_msgs::PoseError::REGION_C);
      ++checked_errors;
    }
    position += e.position_m.norm();
    orientation += angle;
    converged += estimate->converged;
    ++n;
  }
  position /= n;
  orientation /= n;
  std::printf(
      "[ near contact ] %d frames: mean position error %.4f m, mean orientation error %.4f deg\n",
      n, position, orientation);
  EXPECT_GE(checked_errors, 15) << "eval_node published too few /aar/pose_error messages";
  EXPECT_LT(position, 0.10);
  EXPECT_LT(orientation, 1.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "aar_registration_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
