#include <gtest/gtest.h>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_msgs/PoseError.h>
#include <aar_msgs/PoseEstimate.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include "aar_testing/command.h"
#include "aar_testing/logged_errors.h"
#include "aar_testing/paths.h"
#include "aar_testing/stamped_collector.h"
#include "aar_testing/wait.h"

#include <limits>
#include <map>
#include <mutex>
#include <string>

namespace {

TEST(NearContact, NoBoomErrorsUnderTenCentimetresAndOneDegree) {
  ros::NodeHandle nh;
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  aar_testing::StampedCollector<aar_msgs::PoseError> errors(nh, "/aar/pose_error");
  tf2_ros::Buffer tf(ros::Duration(120.0));
  tf2_ros::TransformListener listener(tf);
  aar_testing::WaitFor([&] { return estimates.size() >= 20; }, 200.0);
  ASSERT_GE(estimates.size(), 18u) << "estimates for fewer than 18 of 20 frames";

  double position = 0.0, orientation = 0.0;
  int n = 0, converged = 0, checked_errors = 0;
  std::lock_guard<std::mutex> lock(estimates.mutex);
  for (const auto& [stamp, estimate] : estimates.by_stamp) {
    const auto truth = tf.lookupTransform("tanker", "receiver_truth", stamp, ros::Duration(2.0));
    Eigen::Isometry3d estimated;
    tf2::fromMsg(estimate->pose, estimated);
    const aar_geometry::PoseError e =
        aar_geometry::ComputePoseError(tf2::transformToEigen(truth), estimated);
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

// The last value of each key on /diagnostics, whatever status it came in.
class DiagnosticValues {
 public:
  explicit DiagnosticValues(ros::NodeHandle& nh)
      : sub_(nh.subscribe<diagnostic_msgs::DiagnosticArray>(
            "/diagnostics", 10, [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
              std::lock_guard<std::mutex> lock(mutex_);
              for (const auto& status : msg->status) {
                for (const auto& kv : status.values) values_[kv.key] = kv.value;
              }
            })) {}
  std::string operator[](const std::string& key) {  // "" until it came
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = values_.find(key);
    return it == values_.end() ? std::string() : it->second;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::string> values_;
  ros::Subscriber sub_;  // last: its callback uses the members above
};

sensor_msgs::PointCloud2 Cloud(const std::string& frame, const std::vector<Eigen::Vector3f>& points,
                               bool with_z = true) {
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = frame;
  msg.header.stamp = ros::Time::now();
  sensor_msgs::PointCloud2Modifier modifier(msg);
  if (with_z) {
    modifier.setPointCloud2FieldsByString(1, "xyz");
  } else {
    modifier.setPointCloud2Fields(2, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                                  sensor_msgs::PointField::FLOAT32);
  }
  modifier.resize(points.size());
  if (points.empty()) return msg;  // the iterators start at data.front(): undefined when empty
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y");
  for (size_t i = 0; i < points.size(); ++i, ++x, ++y) *x = points[i].x(), *y = points[i].y();
  if (with_z) {
    sensor_msgs::PointCloud2Iterator<float> z(msg, "z");
    for (size_t i = 0; i < points.size(); ++i, ++z) *z = points[i].z();
  }
  return msg;
}

// Frame "sensor" 35 m aft of the tanker origin, where the receiver flies near contact.
geometry_msgs::TransformStamped SensorMount() {
  geometry_msgs::TransformStamped mount;
  mount.header.frame_id = "tanker";
  mount.child_frame_id = "sensor";
  mount.transform.translation.x = -35.0;
  mount.transform.rotation.w = 1.0;
  return mount;
}

// A cloud of the receiver's rough shape around its origin: a fuselage line and a wing line.
std::vector<Eigen::Vector3f> ReceiverShape() {
  std::vector<Eigen::Vector3f> shape;
  for (int i = -40; i <= 40; ++i) {
    shape.emplace_back(0.1f * i, 0.0f, 0.0f);
    shape.emplace_back(0.5f, 0.2f * i, -0.4f);
  }
  return shape;
}

TEST(BadInput, ErrorsNamedNoEstimateNodeAlive) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 5);
  aar_testing::LoggedErrors errors(nh, "/registration");
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  tf2_ros::Buffer tf_buffer;  // listening from the start: the estimate's tf is sent once
  tf2_ros::TransformListener tf_listener(tf_buffer);
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(SensorMount());
  aar_testing::WaitFor([&] { return clouds.getNumSubscribers() > 0 && errors.Connected(); }, 30.0);
  ASSERT_GT(clouds.getNumSubscribers(), 0u);
  auto logged = [&](const std::string& text) { return errors.Wait(text, 5.0); };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  clouds.publish(Cloud("sensor", {}));
  EXPECT_TRUE(logged("cloud has 0 finite points"));
  clouds.publish(Cloud("sensor", std::vector<Eigen::Vector3f>(50, Eigen::Vector3f(nan, nan, nan))));
  ros::WallDuration(0.3).sleep();
  clouds.publish(Cloud("nowhere", {{1, 2, 3}}));
  EXPECT_TRUE(logged("no tf tanker -> 'nowhere'"));
  clouds.publish(Cloud("sensor", {{1, 2, 3}}, false));
  EXPECT_TRUE(logged("no float32 field 'z'"));
  sensor_msgs::PointCloud2 ragged =
      Cloud("sensor", std::vector<Eigen::Vector3f>(20, Eigen::Vector3f(1, 2, 3)));
  ragged.data.resize(ragged.data.size() +
                     4);  // not a whole number of points: once read past the end
  clouds.publish(ragged);
  EXPECT_TRUE(logged("cloud is malformed"));
  // Stamps no clock gives: 0, and 1e6 s ahead (its pose on tf would make every later estimate
  // TF_OLD_DATA for every listener).
  const std::vector<Eigen::Vector3f> shape = ReceiverShape();
  sensor_msgs::PointCloud2 zero = Cloud("sensor", shape);
  zero.header.stamp = ros::Time(0);
  clouds.publish(zero);
  EXPECT_TRUE(logged("the cloud's stamp is 0"));
  sensor_msgs::PointCloud2 future = Cloud("sensor", shape);
  future.header.stamp += ros::Duration(1e6);
  clouds.publish(future);
  EXPECT_TRUE(logged("s ahead of the clock"));
  {
    std::lock_guard<std::mutex> lock(estimates.mutex);  // only "no pose" replies, for lockstep
    for (const auto& [stamp, e] : estimates.by_stamp)
      EXPECT_FALSE(e->valid) << "a bad cloud produced a pose";
  }
  const size_t invalid = estimates.size();

  // Alive: a cloud of the receiver's shape 35 m aft gives an estimate near there, on tf too.
  const sensor_msgs::PointCloud2 good_cloud = Cloud("sensor", shape);
  clouds.publish(good_cloud);
  aar_testing::WaitFor([&] { return estimates.size() > invalid; }, 10.0);
  ASSERT_EQ(estimates.size(), invalid + 1);
  {
    std::lock_guard<std::mutex> lock(estimates.mutex);
    const auto& good = estimates.by_stamp.at(good_cloud.header.stamp);
    EXPECT_TRUE(good->valid);
    EXPECT_NEAR(good->pose.position.x, -35.0, 5.0);
  }
  EXPECT_TRUE(
      tf_buffer.canTransform("tanker", "receiver", good_cloud.header.stamp, ros::Duration(5.0)));

  // A cloud beyond max_cloud_points (50,000) is registered as a subset of that size, with a
  // warning: 2 million points once kept the node busy for 70 s, saying nothing.
  aar_testing::LoggedErrors warnings(nh, "/registration", 4);  // 4: WARN
  aar_testing::WaitFor([&] { return warnings.Connected(); }, 10.0);
  std::vector<Eigen::Vector3f> many;
  while (many.size() < 60000) many.insert(many.end(), shape.begin(), shape.end());
  const sensor_msgs::PointCloud2 big = Cloud("sensor", many);
  clouds.publish(big);
  EXPECT_TRUE(warnings.Wait("registered a random 50000 of them (max_cloud_points)", 30.0));
  EXPECT_TRUE(aar_testing::WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(estimates.mutex);
        return estimates.by_stamp.count(big.header.stamp) &&
               estimates.by_stamp.at(big.header.stamp)->valid;
      },
      30.0));
}

// Start-up order: the default shelled reference needs the cameras' tf. Without it the node once
// exited FATAL after 10 s (ending a launch that requires it); now it waits, says so, answers
// each cloud with no estimate, and builds the reference once the tf comes.
TEST(StartUp, WaitsForTheCameraTfThenEstimates) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 5);
  aar_testing::LoggedErrors warnings(nh, "/registration", 4);  // 4: WARN
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  aar_testing::WaitFor([&] { return clouds.getNumSubscribers() > 0 && warnings.Connected(); },
                       30.0);
  ASSERT_GT(clouds.getNumSubscribers(), 0u);
  EXPECT_TRUE(warnings.Wait("needed to shell the reference model", 15.0));
  ros::WallDuration(8.0).sleep();  // past the 10 s that once ended the node
  const std::vector<Eigen::Vector3f> shape = ReceiverShape();
  const sensor_msgs::PointCloud2 early = Cloud("sensor", shape);
  clouds.publish(early);
  ASSERT_TRUE(aar_testing::WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(estimates.mutex);
        return estimates.by_stamp.count(early.header.stamp) > 0;
      },
      10.0))
      << "the node is gone or silent";
  {
    std::lock_guard<std::mutex> lock(estimates.mutex);
    EXPECT_FALSE(estimates.by_stamp.at(early.header.stamp)->valid);
  }
  // The cameras 15 m ahead of "sensor", looking aft: the tf comes, the reference follows.
  tf2_ros::StaticTransformBroadcaster static_tf;
  std::vector<geometry_msgs::TransformStamped> mounts = {SensorMount()};
  for (const auto& [frame, y] : {std::make_pair("stereo_left_optical", -0.25),
                                 std::make_pair("stereo_right_optical", 0.25)}) {
    geometry_msgs::TransformStamped m;
    m.header.frame_id = "tanker";
    m.child_frame_id = frame;
    m.transform.translation.x = -20.0;
    m.transform.translation.y = y;
    m.transform.translation.z = -3.0;
    m.transform.rotation.w = 1.0;
    mounts.push_back(m);
  }
  static_tf.sendTransform(mounts);
  ros::Time stamp;
  EXPECT_TRUE(aar_testing::WaitFor(
      [&] {
        const sensor_msgs::PointCloud2 cloud = Cloud("sensor", shape);
        clouds.publish(cloud);
        ros::WallDuration(1.0).sleep();
        std::lock_guard<std::mutex> lock(estimates.mutex);
        const auto it = estimates.by_stamp.find(cloud.header.stamp);
        return it != estimates.by_stamp.end() && it->second->valid;
      },
      30.0))
      << "no estimate after the cameras' tf came";
}

// reference: topic: each cloud is registered to the reference of its own stamp, to the points
// both cameras see (visibility 0); a cloud whose reference never comes gets an invalid estimate.
// The estimate of `stamp` once it has come (null: none within 10 s).
aar_msgs::PoseEstimate::ConstPtr WaitForEstimate(
    aar_testing::StampedCollector<aar_msgs::PoseEstimate>& estimates, const ros::Time& stamp) {
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> lock(estimates.mutex);
      if (estimates.by_stamp.count(stamp)) return estimates.by_stamp.at(stamp);
    }
    ros::WallDuration(0.01).sleep();
  }
  return nullptr;
}

TEST(TopicReference, PairsByStampUsesClassZeroAndAnswersWithoutReference) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 5);
  ros::Publisher references = nh.advertise<sensor_msgs::PointCloud2>("/aar/reference_cloud", 5);
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(SensorMount());
  aar_testing::WaitFor(
      [&] {
        return clouds.getNumSubscribers() > 0 && references.getNumSubscribers() > 0 &&
               estimates.sub.getNumPublishers() > 0;
      },
      30.0);
  ASSERT_GT(references.getNumSubscribers(), 0u);
  auto wait_for = [&](const ros::Time& stamp) { return WaitForEstimate(estimates, stamp); };
  const std::vector<Eigen::Vector3f> shape = ReceiverShape();
  // No reference: answered (invalid) after reference_timeout.
  const auto alone = Cloud("sensor", shape);
  clouds.publish(alone);
  const auto none = wait_for(alone.header.stamp);
  ASSERT_TRUE(none) << "no answer for a cloud without a reference";
  EXPECT_FALSE(none->valid);

  // With a reference of the same stamp: the shape (class 0) plus 300 points of class 3 far off,
  // which would pull the centroid seed 10 m aside if they were used.
  auto cloud = Cloud("sensor", shape);
  std::vector<Eigen::Vector3f> ref_points = shape;
  for (int i = 0; i < 300; ++i) ref_points.emplace_back(0.0f, 40.0f, 0.0f);
  sensor_msgs::PointCloud2 reference;
  reference.header.stamp = cloud.header.stamp;
  reference.header.frame_id = "receiver";
  sensor_msgs::PointCloud2Modifier modifier(reference);
  modifier.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "visibility", 1, sensor_msgs::PointField::UINT8);
  reference.point_step = 16;  // 13 bytes padded: aligned floats for the iterators (UBSan)
  modifier.resize(ref_points.size());
  sensor_msgs::PointCloud2Iterator<float> x(reference, "x");
  sensor_msgs::PointCloud2Iterator<uint8_t> v(reference, "visibility");
  for (size_t i = 0; i < ref_points.size(); ++i, ++x, ++v) {
    x[0] = ref_points[i].x(), x[1] = ref_points[i].y(), x[2] = ref_points[i].z();
    *v = i < shape.size() ? 0 : 3;
  }
  references.publish(reference);
  clouds.publish(cloud);
  const auto paired = wait_for(cloud.header.stamp);
  ASSERT_TRUE(paired) << "no answer for a cloud with its reference";
  EXPECT_TRUE(paired->valid);
  EXPECT_EQ(paired->reference_points, shape.size());
  EXPECT_NEAR(paired->pose.position.x, -35.0, 0.01);
  EXPECT_NEAR(paired->pose.position.y, 0.0, 0.01);
}

// A frame's reference cloud (receiver frame) of `points`, each of visibility class 0.
sensor_msgs::PointCloud2 ReferenceOf(const std::vector<Eigen::Vector3f>& points,
                                     const ros::Time& stamp) {
  sensor_msgs::PointCloud2 reference = Cloud("receiver", points);
  reference.header.stamp = stamp;
  return reference;
}

// Two rigs (issue 44; registration_rigs.test: rigs [stereo, second], rig_wait 0.5 s): a frame's
// clouds are gathered by stamp and registered together against the union of their references;
// a frame whose second rig never comes is registered with the first after rig_wait, counted.
TEST(TwoRigs, CloudsGatheredByStampAndALateRigWaitedForOnlySoLong) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 5);
  ros::Publisher references = nh.advertise<sensor_msgs::PointCloud2>("/aar/reference_cloud", 5);
  ros::Publisher second = nh.advertise<sensor_msgs::PointCloud2>("/second/aar/points_filtered", 5);
  ros::Publisher second_references =
      nh.advertise<sensor_msgs::PointCloud2>("/second/aar/reference_cloud", 5);
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  aar_testing::LoggedErrors warnings(nh, "/registration", 4);  // 4: WARN
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(SensorMount());
  aar_testing::WaitFor(
      [&] {
        return references.getNumSubscribers() > 0 && second.getNumSubscribers() > 0 &&
               second_references.getNumSubscribers() > 0 && estimates.sub.getNumPublishers() > 0;
      },
      30.0);
  ASSERT_GT(second_references.getNumSubscribers(), 0u);
  auto wait_for = [&](const ros::Time& stamp) { return WaitForEstimate(estimates, stamp); };
  // Each rig sees half of the receiver (both "sensor" mounted: one frame for both here); both
  // references are the whole shape, so their union is the shape once.
  const std::vector<Eigen::Vector3f> shape = ReceiverShape();
  const std::vector<Eigen::Vector3f> front(shape.begin(), shape.begin() + shape.size() / 2),
      back(shape.begin() + shape.size() / 2, shape.end());
  const auto first_half = Cloud("sensor", front);
  auto second_half = Cloud("sensor", back);
  second_half.header.stamp = first_half.header.stamp;
  second.publish(second_half);  // the second rig first: the frame waits for the first
  second_references.publish(ReferenceOf(shape, first_half.header.stamp));
  ros::WallDuration(0.1).sleep();
  references.publish(ReferenceOf(shape, first_half.header.stamp));
  clouds.publish(first_half);
  const auto both = wait_for(first_half.header.stamp);
  ASSERT_TRUE(both) << "no answer for a frame both rigs sent";
  EXPECT_TRUE(both->valid);
  EXPECT_EQ(both->sensed_points, shape.size());
  EXPECT_EQ(both->reference_points, shape.size());
  EXPECT_NEAR(both->pose.position.x, -35.0, 0.01);

  // The second rig never sends this frame: registered with the first's after rig_wait.
  const auto alone = Cloud("sensor", shape);
  references.publish(ReferenceOf(shape, alone.header.stamp));
  clouds.publish(alone);
  const ros::WallTime sent = ros::WallTime::now();
  const auto late = wait_for(alone.header.stamp);
  const double waited = (ros::WallTime::now() - sent).toSec();
  ASSERT_TRUE(late) << "no answer for a frame the second rig did not send";
  EXPECT_TRUE(late->valid);
  EXPECT_EQ(late->sensed_points, shape.size());
  EXPECT_GT(waited, 0.45);  // rig_wait 0.5 s (the expiry timer ticks every 0.1 s)
  EXPECT_LT(waited, 2.0);
  const std::string named = warnings.WaitMessage("registered without the clouds of second", 5.0);
  EXPECT_NE(named.find("second (1 such frames so far)"), std::string::npos)
      << "not named: " << named;
}

// Tracking in the node: the receiver (every 8th dense sample) flies past "sensor" at 0.5 m/s, 10
// clouds a second. Clouds with no receiver coast on the prediction (valid, TRACK_REJECTED) until
// max_rejections (3) loses the track (invalid, TRACK_LOST); the receiver back starts a new one;
// the clock and the stamps going back (a bag loop) start one again; a cloud that comes late (its
// stamp before the last one, the clock going on) is dropped with a warning naming both stamps,
// and the track goes on; a cloud of NaN points never gives a NaN pose. Counts and the last event
// are on /diagnostics.
TEST(Tracking, CoastsLosesReacquiresAndResetsOnStampsGoingBack) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 20);
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 5);
  aar_testing::LoggedErrors warnings(nh, "/registration", rosgraph_msgs::Log::WARN);
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  DiagnosticValues diagnostics(nh);
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(SensorMount());
  aar_testing::WaitFor(
      [&] {
        return clouds.getNumSubscribers() > 0 && clock.getNumSubscribers() > 0 &&
               estimates.sub.getNumPublishers() > 0 && warnings.Connected();
      },
      30.0);
  ASSERT_GT(clouds.getNumSubscribers(), 0u);
  const auto dense = aar_geometry::SampleReceiver(
      aar_geometry::LoadMesh(aar_testing::ModelsDir() + "/receiver.obj"), {});
  auto receiver_at = [&](double x) {  // in "sensor", 35 m aft of the tanker
    std::vector<Eigen::Vector3f> points;
    const Eigen::Isometry3d T = aar_geometry::MakeTransform({x, 0.2, 0.0}, {0.0, -0.035, 0.0});
    for (size_t i = 0; i < dense.size(); i += 8)
      points.push_back((T * dense.points[i]).cast<float>());
    return points;
  };
  const std::vector<Eigen::Vector3f> nothing(30, Eigen::Vector3f(2000.0f, 0.0f, 0.0f));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> nans(30, Eigen::Vector3f(nan, nan, nan));
  double t = 0.0, clock_s = 0.0;  // the next cloud's stamp and the clock [s after 100 s]
  // The clock at `t` [s]; the next message sent comes after it.
  auto set_clock = [&](double at) {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(100.0 + at);
    clock.publish(c);
    ros::WallDuration(0.05).sleep();
  };
  // Publishes one cloud at `t` [s] and waits for its estimate, the clock at `t` first.
  auto send = [&](double at, const std::vector<Eigen::Vector3f>& points, double wait = 10.0) {
    clock_s = std::max(at, clock_s);
    set_clock(clock_s);
    auto cloud = Cloud("sensor", points);
    cloud.header.stamp = ros::Time(100.0 + at);
    clouds.publish(cloud);
    aar_msgs::PoseEstimate::ConstPtr got;
    aar_testing::WaitFor(
        [&] {
          std::lock_guard<std::mutex> lock(estimates.mutex);
          const auto it = estimates.by_stamp.find(cloud.header.stamp);
          if (it != estimates.by_stamp.end()) got = it->second;
          return got != nullptr;
        },
        wait);
    return got;
  };
  using E = aar_msgs::PoseEstimate;
  std::vector<uint8_t> tracks;
  std::vector<bool> valid;
  auto step = [&](const std::vector<Eigen::Vector3f>& points) {
    const auto e = send(t, points);
    t += 0.1;
    if (!e) {
      ADD_FAILURE() << "no estimate at " << t - 0.1 << " s";
      return;
    }
    EXPECT_TRUE(std::isfinite(e->pose.position.x) && std::isfinite(e->pose.orientation.w));
    for (double c : e->covariance) EXPECT_TRUE(std::isfinite(c));
    tracks.push_back(e->track);
    valid.push_back(e->valid);
  };
  for (int k = 0; k < 6; ++k) step(receiver_at(0.05 * k));  // 0-5: started, then accepted
  step(nothing);                                            // 6, 7: coasting
  step(nans);
  step(nothing);                                       // 8: the third: lost
  for (int k = 0; k < 3; ++k) step(receiver_at(0.3));  // 9: started, 10-11 accepted
  t = clock_s = 0.25;                                  // 12: the clock back too: a bag loop
  step(receiver_at(0.3));
  step(receiver_at(0.3));  // 13: accepted
  // A cloud that comes late, stamped before the last one, the clock going on: no estimate.
  const auto late = send(0.32, receiver_at(0.3), 2.0);
  EXPECT_FALSE(late) << "a late cloud was registered (track " << static_cast<int>(late->track)
                     << ": " << late->track_reason << ")";
  EXPECT_TRUE(warnings.Wait(
      "registration: cloud on /points dropped, no estimate: stamp 100.320000000 is 0.030 s "
      "before the last one taken, 100.350000000: out of order",
      5.0));
  step(receiver_at(0.3));  // 14: the track went on
  ASSERT_EQ(tracks.size(), 15u);
  const std::vector<uint8_t> expected = {E::TRACK_STARTED,  E::TRACK_ACCEPTED, E::TRACK_ACCEPTED,
                                         E::TRACK_ACCEPTED, E::TRACK_ACCEPTED, E::TRACK_ACCEPTED,
                                         E::TRACK_REJECTED, E::TRACK_REJECTED, E::TRACK_LOST,
                                         E::TRACK_STARTED,  E::TRACK_ACCEPTED, E::TRACK_ACCEPTED,
                                         E::TRACK_STARTED,  E::TRACK_ACCEPTED, E::TRACK_ACCEPTED};
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(static_cast<int>(tracks[k]), static_cast<int>(expected[k])) << "cloud " << k;
    EXPECT_EQ(valid[k], k != 8) << "cloud " << k;  // coasting is an estimate; lost is not
  }
  {
    std::lock_guard<std::mutex> lock(estimates.mutex);
    const auto& reset = estimates.by_stamp.at(ros::Time(100.25));
    EXPECT_NE(reset->track_reason.find("stamp went back"), std::string::npos)
        << reset->track_reason;
    EXPECT_EQ(reset->seed, E::SEED_CENTROID);
    EXPECT_EQ(estimates.by_stamp.at(ros::Time(100.5))->seed, E::SEED_PREDICTION);
    EXPECT_GT(estimates.by_stamp.at(ros::Time(100.5))->covariance[0], 0.0);
  }
  aar_testing::WaitFor([&] { return diagnostics["frames"] == "15"; }, 5.0);
  EXPECT_EQ(diagnostics["ledger: frames dropped: out_of_order"], "1");
  EXPECT_EQ(diagnostics["frames lost"], "1");
  EXPECT_EQ(diagnostics["frames rejected"], "2");
  EXPECT_EQ(diagnostics["frames started"], "3");
  EXPECT_NE(diagnostics["last track event"].find("stamp went back"), std::string::npos)
      << diagnostics["last track event"];
}

// newest_wins: 40 clouds of the receiver sent at once, far faster than registration. A stage that
// falls behind registers the cloud in hand, then the newest: each cloud is either registered
// (an estimate) or counted as superseded on /diagnostics, none is lost unseen, and the last one
// is always registered. With newest_wins off the subscriber queue (2) drops clouds unseen and the
// counts do not add up.
TEST(NewestWins, ABurstOfCloudsIsRegisteredOrCountedNoneLostUnseen) {
  ros::NodeHandle nh;
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>("/points", 100);
  aar_testing::StampedCollector<aar_msgs::PoseEstimate> estimates(nh, "/aar/pose_estimate");
  DiagnosticValues diagnostics(nh);
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(SensorMount());
  aar_testing::WaitFor(
      [&] { return clouds.getNumSubscribers() > 0 && estimates.sub.getNumPublishers() > 0; }, 30.0);
  ASSERT_GT(clouds.getNumSubscribers(), 0u);
  const auto dense = aar_geometry::SampleReceiver(
      aar_geometry::LoadMesh(aar_testing::ModelsDir() + "/receiver.obj"), {});
  std::vector<Eigen::Vector3f> receiver;
  const Eigen::Isometry3d T = aar_geometry::MakeTransform({0.3, 0.2, 0.0}, {0.0, -0.035, 0.0});
  for (size_t i = 0; i < dense.size(); i += 2)
    receiver.push_back((T * dense.points[i]).cast<float>());
  // One cloud first, registered alone: the node is up and its tf is there.
  sensor_msgs::PointCloud2 cloud = Cloud("sensor", receiver);
  const ros::Time first = ros::Time::now() - ros::Duration(0.5);
  cloud.header.stamp = first;
  clouds.publish(cloud);
  ASSERT_TRUE(aar_testing::WaitFor([&] { return estimates.size() == 1; }, 20.0));
  constexpr int kBurst = 40;
  for (int k = 1; k <= kBurst; ++k) {
    cloud.header.stamp = first + ros::Duration(0.01 * k);
    clouds.publish(cloud);
  }
  const ros::Time last = cloud.header.stamp;
  auto count = [&](const std::string& key) {
    const std::string value = diagnostics[key];
    return value.empty() ? -1 : std::stoi(value);
  };
  const std::string kSuperseded = "ledger: frames dropped: superseded";
  aar_testing::WaitFor([&] { return count("frames") + count(kSuperseded) == kBurst + 1; }, 20.0);
  const int frames = count("frames"), superseded = count(kSuperseded);
  std::printf("[ newest wins ] %d clouds: %d registered, %d superseded\n", kBurst + 1, frames,
              superseded);
  EXPECT_EQ(frames + superseded, kBurst + 1) << "clouds lost unseen";
  EXPECT_GE(superseded, 1) << "the burst did not overload the node: the test shows nothing";
  std::lock_guard<std::mutex> lock(estimates.mutex);
  EXPECT_EQ(static_cast<int>(estimates.by_stamp.size()), frames);
  EXPECT_EQ(estimates.by_stamp.count(last), 1u) << "the newest cloud was not registered";
}

TEST(BadInput, MissingReferenceMeshExitsNamingIt) {
  const auto r = aar_testing::RunCommand(
      "timeout 30 rosrun aar_registration registration_node __name:=bad_mesh _reference:=dense "
      "_receiver:=/nonexistent/receiver.obj");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/receiver.obj"), std::string::npos) << r.output;
}

// A receiver mesh in millimetres (13 km long) and an open one stop the node, the file and the
// figure named.
TEST(BadInput, ReceiverInWrongUnitsOrOpenExitsNamingIt) {
  const std::string mm = ::testing::TempDir() + "/receiver_mm.obj";
  aar_geometry::WriteObj(
      mm, aar_geometry::Scaled(aar_geometry::LoadMesh(aar_testing::ModelsDir() + "/receiver.obj"),
                               Eigen::Vector3d::Constant(1000.0)));
  auto r = aar_testing::RunCommand(
      "timeout 30 rosrun aar_registration registration_node __name:=mm_mesh _reference:=dense "
      "_receiver:=" +
      mm);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(mm + ": the receiver model is 16610 m across"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("millimetres"), std::string::npos) << r.output;
  // The C-12's mesh alone, without its description's allowance for the open fin root.
  r = aar_testing::RunCommand(
      "timeout 30 rosrun aar_registration registration_node __name:=open_mesh _reference:=dense "
      "_receiver:=" +
      aar_testing::ModelsDir() + "/receiver.obj");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("receiver.obj: the receiver model is open: 22 of 144 edges"),
            std::string::npos)
      << r.output;
  std::remove(mm.c_str());
}

}  // namespace
