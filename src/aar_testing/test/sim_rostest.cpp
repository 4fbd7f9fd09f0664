#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include <aar_geometry/robot_model.h>
#include <aar_msgs/PoseEstimate.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/JointState.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_listener.h>

#include <aar_description/boom_model.h>
#include "aar_sim/flight_path.h"
#include "aar_sim/ros/sim_node.h"
#include "aar_sim/turbulence.h"
#include "aar_testing/paths.h"
#include "aar_testing/stamped_collector.h"
#include "aar_testing/wait.h"

namespace aar_sim {

using aar_description::BoomJointPositions;
using aar_description::DefaultBoomPose;
namespace {

template <typename Msg>
using Collector = aar_testing::StampedCollector<Msg>;

TEST(Sim, StereoPairsCameraInfosAndTruth) {
  ros::NodeHandle nh, pnh("~");
  Collector<sensor_msgs::Image> left(nh, "stereo/left/image_rect"),
      right(nh, "stereo/right/image_rect");
  Collector<sensor_msgs::CameraInfo> left_info(nh, "stereo/left/camera_info"),
      right_info(nh, "stereo/right/camera_info");
  Collector<sensor_msgs::JointState> joints(nh, "joint_states");
  // sim.test's second rig, `port`: its pairs under the same stamps, in its namespace and frames.
  Collector<sensor_msgs::Image> port_left(nh, "port/left/image_rect");
  Collector<sensor_msgs::CameraInfo> port_right_info(nh, "port/right/camera_info");
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  aar_testing::WaitFor(
      [&] {
        return left.size() >= 4 && right_info.size() >= 4 && joints.size() >= 4 &&
               port_left.size() >= 4 && port_right_info.size() >= 4;
      },
      60.0);
  ros::WallDuration(0.5).sleep();  // let tf catch up with the last frames
  ASSERT_GE(left.size(), 4u) << "fewer than 4 stereo frames in 60 s";
  ASSERT_GE(port_left.size(), 4u) << "fewer than 4 pairs of the second rig, port, in 60 s";

  std::string path_file;
  ASSERT_TRUE(pnh.getParam("flight_path", path_file));
  const FlightPath path = FlightPath::Load(path_file);
  const double fx = 320.0 / std::tan(25.0 * M_PI / 180.0);  // 640 px wide, 50 deg
  int checked = 0, port_checked = 0;
  std::lock_guard<std::mutex> l1(left.mutex), l2(right.mutex), l3(left_info.mutex),
      l4(right_info.mutex), l6(port_left.mutex), l7(port_right_info.mutex);
  for (const auto& [stamp, image] : left.by_stamp) {
    if (!right.by_stamp.count(stamp) || !left_info.by_stamp.count(stamp) ||
        !right_info.by_stamp.count(stamp))
      continue;
    const auto& r = right.by_stamp.at(stamp);
    const auto& li = left_info.by_stamp.at(stamp);
    const auto& ri = right_info.by_stamp.at(stamp);
    EXPECT_EQ(image->encoding, "mono8");
    EXPECT_EQ(image->width, 640u);
    EXPECT_EQ(image->height, 480u);
    EXPECT_EQ(r->header.stamp, image->header.stamp);
    EXPECT_EQ(image->header.frame_id, "stereo_left_optical");
    EXPECT_EQ(r->header.frame_id, "stereo_left_optical");  // ROS stereo convention (image_geometry)
    EXPECT_EQ(ri->header.frame_id, "stereo_left_optical");
    EXPECT_NEAR(li->K[0], fx, 1e-6);
    EXPECT_NEAR(li->K[4], fx, 1e-6);
    EXPECT_NEAR(li->K[2], 319.5, 1e-9);
    EXPECT_NEAR(li->K[5], 239.5, 1e-9);
    EXPECT_EQ(li->P[3], 0.0);
    EXPECT_NEAR(ri->P[3], -fx * 0.6, 1e-6);  // Tx = -f * baseline
    EXPECT_EQ(li->width, 640u);

    // Truth tf equals the flight path at the frame's time (stamp = 1 s + path time).
    const auto truth =
        tf_buffer.lookupTransform("tanker", "receiver_truth", stamp, ros::Duration(1.0));
    const Eigen::Isometry3d T = tf2::transformToEigen(truth);
    const Eigen::Isometry3d expected = path.At(stamp.toSec() - 1.0).T_tanker_receiver();
    EXPECT_LT((T.translation() - expected.translation()).norm(), 1e-6);
    EXPECT_LT(Eigen::AngleAxisd(T.linear().transpose() * expected.linear()).angle(), 1e-6);
    // The stereo mount: right camera 0.6 m along the left camera's x axis.
    const auto mount = tf_buffer.lookupTransform("stereo_left_optical", "stereo_right_optical",
                                                 stamp, ros::Duration(1.0));
    EXPECT_NEAR(mount.transform.translation.x, 0.6, 1e-9);
    ++checked;
    // The second rig: the frame's stamp, its own frame, the top-level baseline, its mount.
    if (!port_left.by_stamp.count(stamp) || !port_right_info.by_stamp.count(stamp)) continue;
    const auto& port = port_left.by_stamp.at(stamp);
    EXPECT_EQ(port->header.frame_id, "port_left_optical");
    EXPECT_NE(port->data, image->data);  // another view
    EXPECT_NEAR(port_right_info.by_stamp.at(stamp)->P[3], -fx * 0.6, 1e-6);
    const Eigen::Isometry3d port_mount = tf2::transformToEigen(
        tf_buffer.lookupTransform("tanker", "port_left_optical", stamp, ros::Duration(1.0)));
    EXPECT_LT(
        (port_mount * Eigen::Vector3d(0.3, 0.0, 0.0) - Eigen::Vector3d(-15.0, -1.0, -4.0)).norm(),
        1e-9);
    ++port_checked;
  }
  EXPECT_GE(checked, 3);
  EXPECT_GE(port_checked, 3);

  // Boom links from robot_state_publisher agree with the URDF's kinematics at the joint states.
  const auto nozzle =
      tf_buffer.lookupTransform("tanker", "nozzle_tip", ros::Time(0), ros::Duration(2.0));
  aar_geometry::RobotModelOptions urdf_options;
  const auto boom = aar_geometry::LoadRobotModel(
      ros::package::getPath("aar_description") + "/models/boom.urdf", urdf_options);
  const auto poses = aar_geometry::ComputeLinkPoses(boom, BoomJointPositions(DefaultBoomPose()));
  EXPECT_LT(
      (tf2::transformToEigen(nozzle).translation() - poses.at("nozzle_tip").translation()).norm(),
      1e-6);
  std::lock_guard<std::mutex> l5(joints.mutex);
  const auto& js = joints.by_stamp.begin()->second;
  ASSERT_EQ(js->name.size(), 3u);
}

// With turbulence (sim_turbulence.test: moderate, seed 3), the published truth and joint states
// are the path perturbed by aar_sim::Turbulence at the frame's time: decimetres off the path,
// the boom off its static pose and within its limits.
TEST(SimTurbulence, TruthIsThePerturbedPath) {
  ros::NodeHandle nh, pnh("~");
  Collector<sensor_msgs::Image> left(nh, "stereo/left/image_rect");
  Collector<sensor_msgs::JointState> joints(nh, "joint_states");
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  aar_testing::WaitFor([&] { return left.size() >= 4 && joints.size() >= 4; }, 60.0);
  ros::WallDuration(0.5).sleep();  // let tf catch up with the last frames
  ASSERT_GE(joints.size(), 4u) << "fewer than 4 frames in 60 s";

  std::string path_file;
  ASSERT_TRUE(pnh.getParam("flight_path", path_file));
  aar_geometry::RobotModelOptions urdf_options;
  const auto boom_model = aar_geometry::LoadRobotModel(
      ros::package::getPath("aar_description") + "/models/boom.urdf", urdf_options);
  const FlightPath path = FlightPath::Load(path_file);
  TurbulenceOptions options;
  options.intensity = TurbulenceIntensity::kModerate;
  options.seed = 3;
  const Turbulence turbulence(options, path.end_time());
  int checked = 0;
  double max_offset = 0.0, max_boom = 0.0;
  std::lock_guard<std::mutex> lock(joints.mutex);
  for (const auto& [stamp, js] : joints.by_stamp) {
    const double t = stamp.toSec() - 1.0;
    const FlightPathRow row = path.At(t);
    const auto [expected_row, expected_boom] =
        turbulence.Apply(t, row, row.boom.value_or(DefaultBoomPose()), boom_model.joints);
    const auto truth =
        tf_buffer.lookupTransform("tanker", "receiver_truth", stamp, ros::Duration(1.0));
    const Eigen::Isometry3d T = tf2::transformToEigen(truth);
    const Eigen::Isometry3d expected = expected_row.T_tanker_receiver();
    EXPECT_LT((T.translation() - expected.translation()).norm(), 1e-6) << t;
    EXPECT_LT(Eigen::AngleAxisd(T.linear().transpose() * expected.linear()).angle(), 1e-6) << t;
    max_offset = std::max(max_offset, (T.translation() - row.position_m).norm());
    const std::map<std::string, double> want = BoomJointPositions(expected_boom);
    ASSERT_EQ(js->name.size(), want.size());
    for (size_t i = 0; i < js->name.size(); ++i) {
      EXPECT_NEAR(js->position[i], want.at(js->name[i]), 1e-9) << js->name[i] << " at " << t;
      for (const auto& joint : boom_model.joints) {
        if (joint.name == js->name[i]) {
          EXPECT_TRUE(joint.WithinLimits(js->position[i])) << joint.name;
        }
      }
    }
    max_boom = std::max(max_boom, std::abs(expected_boom.pitch - DefaultBoomPose().pitch));
    ++checked;
  }
  EXPECT_GE(checked, 4);
  EXPECT_GT(max_offset, 0.02);  // [m] moderate: decimetres
  EXPECT_GT(max_boom, 0.01 * M_PI / 180.0);
}

TEST(Sim, ShippedYamlLoads) {
  const SimNodeOptions o = LoadSimNodeOptions(ros::NodeHandle("/yaml_check"));
  EXPECT_EQ(o.world.rig.intrinsics.width, 1280);
  EXPECT_EQ(o.world.rig.intrinsics.height, 960);
  EXPECT_NEAR(o.world.rig.baseline, 0.5, 1e-12);
  EXPECT_NEAR(o.rate, 10.0, 1e-12);
  EXPECT_FALSE(o.lockstep);
  // DESIGN mount: about 20 m aft and 3 m below the tanker origin; 1 m left of the boom plane.
  const Eigen::Vector3d centre = o.world.rig.T_tanker_left_optical * Eigen::Vector3d(0.25, 0, 0);
  EXPECT_TRUE(centre.isApprox(Eigen::Vector3d(-20.0, 1.0, -3.0), 1e-9));
}

// Runs sim_node with extra arguments (and environment assignments `env`) and returns its exit
// code; its output goes to `log`.
int RunSim(const std::string& args, std::string* log, const std::string& env = "") {
  const std::string out = "/tmp/aar_sim_rostest_" + std::to_string(::getpid()) + ".log";
  const std::string command = env + " timeout 30 " + std::string("rosrun aar_sim sim_node") + " " +
                              args + " > " + out + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  *log = s.str();
  std::remove(out.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Sim, BadInputExitsNonZeroNamingTheProblem) {
  std::string log;
  EXPECT_EQ(RunSim("__name:=bad_path _flight_path:=/nonexistent/path.csv", &log), 1);
  EXPECT_NE(log.find("/nonexistent/path.csv"), std::string::npos) << log;
  EXPECT_EQ(RunSim("__name:=no_path", &log), 1);
  EXPECT_NE(log.find("flight_path"), std::string::npos) << log;
  EXPECT_NE(log.find("required"), std::string::npos) << log;
  const std::string path = aar_testing::DefaultApproachPath();
  EXPECT_EQ(RunSim("__name:=typo _flight_path:=" + path + " _image_widht:=320", &log), 1);
  EXPECT_NE(log.find("unknown parameter /typo/image_widht"), std::string::npos) << log;
  EXPECT_EQ(
      RunSim("__name:=no_mesh _flight_path:=" + path + " _receiver:=/nonexistent/receiver.obj",
             &log),
      1);
  EXPECT_NE(log.find("/nonexistent/receiver.obj"), std::string::npos) << log;
  EXPECT_EQ(
      RunSim("__name:=no_urdf _flight_path:=" + path + " _boom_urdf:=/nonexistent/boom.urdf", &log),
      1);
  EXPECT_NE(log.find("/nonexistent/boom.urdf"), std::string::npos) << log;
  EXPECT_EQ(RunSim("__name:=early _flight_path:=" + path + " _start_time:=-5.0", &log), 1);
  EXPECT_NE(log.find("start_time -5.000000 s is outside the flight path"), std::string::npos)
      << log;
  EXPECT_EQ(RunSim("__name:=stopped _flight_path:=" + path + " _realtime_factor:=0.0", &log), 1);
  EXPECT_NE(log.find("realtime_factor must be above 0 and at most 100"), std::string::npos) << log;
  // No EGL vendor library: as on a machine without Mesa's or a GPU's EGL.
  EXPECT_EQ(RunSim("__name:=no_egl _flight_path:=" + path, &log,
                   "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json"),
            1);
  EXPECT_NE(log.find("no EGL display available"), std::string::npos) << log;
}

TEST(Lockstep, NextFrameOnlyAfterTheEstimate) {
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> left(nh, "stereo/left/image_rect"),
      right(nh, "stereo/right/image_rect");
  ros::Publisher estimates = nh.advertise<aar_msgs::PoseEstimate>("aar/pose_estimate", 10);
  auto wait_for = [&](size_t n, double seconds) {
    aar_testing::WaitFor([&] { return left.size() >= n; }, seconds);
    return left.size();
  };
  ASSERT_EQ(wait_for(1, 30.0), 1u) << "no first frame";
  for (int k = 1; k <= 3; ++k) {
    // Held: no further frame while the estimate is outstanding (timeout is 3 s).
    EXPECT_EQ(wait_for(k + 1, 1.5), static_cast<size_t>(k));
    aar_msgs::PoseEstimate estimate;
    {
      std::lock_guard<std::mutex> lock(left.mutex);
      estimate.header.stamp = left.by_stamp.rbegin()->first;
    }
    estimates.publish(estimate);
    EXPECT_EQ(wait_for(k + 1, 2.0), static_cast<size_t>(k + 1))
        << "frame " << k << " did not follow its estimate";
  }
  // Without an estimate the sim goes on after the timeout.
  EXPECT_EQ(wait_for(5, 6.0), 5u);
}

}  // namespace
}  // namespace aar_sim
