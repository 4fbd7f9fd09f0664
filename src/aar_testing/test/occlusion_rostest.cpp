// occlusion_node in a graph of its own: the test publishes the camera mounts, the boom's joint
// states (robot_state_publisher turns them into link tf) and synthetic clouds whose points carry
// their truth (boom or receiver) in an extra field, which the node must carry through.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include <aar_description/boom_model.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/surface_sampling.h>
#include <aar_ros_common/point_cloud.h>
#include <aar_sim/camera.h>
#include <aar_testing/paths.h>
#include <aar_testing/stamped_collector.h>
#include <aar_testing/wait.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

namespace {

const std::string kModels = aar_testing::ModelsDir();

// Publishes the mounts and, unless told not to, the boom's joint states at 20 Hz.
class Graph {
 public:
  explicit Graph(bool joint_states) {
    rig_ =
        aar_sim::MakeStereoRig(aar_sim::CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0), 0.5);
    std::vector<geometry_msgs::TransformStamped> mounts;
    for (const auto& [frame, T] :
         {std::make_pair("stereo_left_optical", rig_.T_tanker_left_optical),
          std::make_pair("stereo_right_optical", rig_.T_tanker_right_optical())}) {
      geometry_msgs::TransformStamped m = tf2::eigenToTransform(T);
      m.header.frame_id = "tanker";
      m.child_frame_id = frame;
      mounts.push_back(m);
    }
    static_tf_.sendTransform(mounts);
    if (joint_states) {
      joint_pub_ = nh_.advertise<sensor_msgs::JointState>("/joint_states", 10);
      timer_ = nh_.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) {
        sensor_msgs::JointState js;
        js.header.stamp = ros::Time::now();
        for (const auto& [name, q] :
             aar_description::BoomJointPositions(aar_description::DefaultBoomPose())) {
          js.name.push_back(name);
          js.position.push_back(q);
        }
        joint_pub_.publish(js);
      });
    }
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/stereo/points2", 5);
  }

  const aar_sim::StereoRig& rig() const { return rig_; }
  ros::Publisher& cloud_pub() { return cloud_pub_; }

 private:
  ros::NodeHandle nh_;
  aar_sim::StereoRig rig_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  ros::Publisher joint_pub_, cloud_pub_;
  ros::WallTimer timer_;
};

// Points on the boom (visual surface) and the receiver surface the left camera sees, at contact.
struct Scene {
  std::vector<Eigen::Vector3d> points;  // tanker frame
  std::vector<float> truth;             // 1 boom, 0 receiver
};

Scene MakeScene(const Eigen::Vector3d& eye) {
  const auto model = aar_testing::LoadBoomModel();
  const auto links = aar_geometry::ComputeLinkPoses(
      model, aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));
  const auto boom = aar_geometry::RobotMesh(model, links, aar_geometry::GeometryKind::kVisual);
  aar_geometry::TriangleMesh receiver = aar_geometry::Transformed(
      aar_geometry::LoadMesh(kModels + "/receiver.obj"),
      aar_geometry::MakeTransform({-35.0, 0.0, -10.19}, {0.0, -0.035, 0.0}));
  aar_geometry::TriangleMesh both = receiver;
  both.Append(boom);
  const aar_geometry::VisibilityTester rays(both);
  Scene scene;
  aar_geometry::SurfaceSamplingOptions sampling;
  sampling.seed = 11;
  for (int which = 0; which < 2; ++which) {
    sampling.num_points = which == 0 ? 2000 : 12000;
    const auto s = aar_geometry::SampleSurface(which == 0 ? boom : receiver, sampling);
    const auto seen = rays.Visible(s.points, s.normals, eye, 0.01);
    for (size_t i = 0; i < s.points.size(); ++i) {
      if (!seen[i]) continue;
      scene.points.push_back(s.points[i]);
      scene.truth.push_back(which == 0 ? 1.0f : 0.0f);
    }
  }
  return scene;
}

sensor_msgs::PointCloud2 ToCloud(const Scene& scene, const Eigen::Isometry3d& T_left_tanker,
                                 const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = "stereo_left_optical";
  const char* names[] = {"x", "y", "z", "truth"};
  for (uint32_t k = 0; k < 4; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  msg.point_step = 16;
  msg.height = 1;
  msg.width = static_cast<uint32_t>(scene.points.size());
  msg.row_step = msg.point_step * msg.width;
  msg.data.resize(msg.row_step);
  for (size_t i = 0; i < scene.points.size(); ++i) {
    const Eigen::Vector3f p = (T_left_tanker * scene.points[i]).cast<float>();
    std::memcpy(&msg.data[16 * i], p.data(), 12);
    std::memcpy(&msg.data[16 * i + 12], &scene.truth[i], 4);
  }
  return msg;
}

std::vector<double> Truth(const sensor_msgs::PointCloud2& msg) {
  const auto cloud = aar_ros_common::FromCloud(msg);
  return aar_ros_common::ReadField(msg, "truth", cloud.indices);
}

using aar_testing::WaitFor;

struct Diagnostics {
  std::mutex mutex;
  std::string message;
  int level = -1;
  ros::Subscriber sub;
  explicit Diagnostics(ros::NodeHandle& nh) {
    sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 10, [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          for (const auto& s : m->status) {
            if (s.name.find("occlusion") == std::string::npos) continue;
            std::lock_guard<std::mutex> lock(mutex);
            message = s.message;
            level = s.level;
          }
        });
  }
};

struct Outputs {
  explicit Outputs(ros::NodeHandle& nh)
      : filtered(nh, "/aar/points_filtered"),
        boom(nh, "/aar/boom_points"),
        reference(nh, "/aar/reference_cloud"),
        diagnostics(nh) {}
  aar_testing::StampedCollector<sensor_msgs::PointCloud2> filtered, boom, reference;
  Diagnostics diagnostics;

  // Connected to the node's outputs (else the first answers may be lost).
  bool Connected() {
    return WaitFor(
        [&] {
          return filtered.sub.getNumPublishers() > 0 && boom.sub.getNumPublishers() > 0 &&
                 reference.sub.getNumPublishers() > 0;
        },
        30.0);
  }

  // Both clouds for a stamp, or fails the test.
  bool Await(const ros::Time& stamp) {
    return WaitFor(
        [&] {
          std::lock_guard<std::mutex> a(filtered.mutex), b(boom.mutex);
          return filtered.by_stamp.count(stamp) && boom.by_stamp.count(stamp);
        },
        20.0);
  }
};

TEST(Occlusion, CullsTheBoomAndBuildsTheReference) {
  ros::NodeHandle nh;
  Graph graph(true);
  Outputs out(nh);
  std::mutex marker_mutex;
  visualization_msgs::MarkerArray markers;
  ros::Subscriber marker_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/aar/shadow_volumes", 2, [&](const visualization_msgs::MarkerArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(marker_mutex);
        markers = *m;
      });
  ASSERT_TRUE(WaitFor([&] { return graph.cloud_pub().getNumSubscribers() > 0; }, 30.0));
  ASSERT_TRUE(out.Connected());
  // The boom's link tf flowing (robot_state_publisher connects to our joint states first).
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  ASSERT_TRUE(WaitFor([&] { return tf.canTransform("tanker", "telescope", ros::Time(0)); }, 30.0));
  const Scene scene = MakeScene(graph.rig().T_tanker_left_optical.translation());
  const ros::Time stamp = ros::Time::now();
  graph.cloud_pub().publish(ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), stamp));
  ASSERT_TRUE(out.Await(stamp));

  const auto kept = Truth(*out.filtered.by_stamp.at(stamp));
  const auto removed = Truth(*out.boom.by_stamp.at(stamp));
  const size_t boom_total = std::count(scene.truth.begin(), scene.truth.end(), 1.0f);
  const size_t receiver_total = scene.truth.size() - boom_total;
  const size_t boom_removed = std::count(removed.begin(), removed.end(), 1.0);
  const size_t receiver_removed = removed.size() - boom_removed;
  std::printf("[ occlusion ] %zu boom points, %zu removed; %zu receiver points, %zu removed\n",
              boom_total, boom_removed, receiver_total, receiver_removed);
  EXPECT_EQ(kept.size() + removed.size(), scene.points.size());  // a partition, fields kept
  EXPECT_GT(boom_total, 500u);
  EXPECT_GE(boom_removed + 1, boom_total);  // measured: 676 of 676
  // Exact surface points, no stereo: what goes is receiver seen within 2 cm of the boom's outline
  // or 10 cm of it in depth, and past corners of the collision boxes that stand clear of the
  // visual boom (1.5 % here; 0.84 % on rendered frames, culling_oracle_test).
  EXPECT_LE(receiver_removed, 0.02 * receiver_total);

  // The dynamic reference: receiver frame, the cloud's stamp, classes, some hidden by the boom.
  ASSERT_TRUE(WaitFor([&] { return out.reference.size() > 0; }, 10.0));
  const auto reference = out.reference.by_stamp.at(stamp);
  EXPECT_EQ(reference->header.frame_id, "receiver");
  const auto ref = aar_ros_common::FromCloud(*reference);
  const auto classes = aar_ros_common::ReadField(*reference, "visibility", ref.indices);
  ASSERT_TRUE(aar_ros_common::HasField(*reference, "normal_z"));
  const size_t both = std::count(classes.begin(), classes.end(), 0.0);
  std::printf("[ occlusion ] reference: %zu points, %zu seen by both cameras\n", classes.size(),
              both);
  EXPECT_GT(both, classes.size() / 3);
  EXPECT_LT(both, classes.size());
  for (const double c : classes) EXPECT_TRUE(c >= 0.0 && c <= 3.0);

  ASSERT_TRUE(WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(marker_mutex);
        return !markers.markers.empty();
      },
      10.0));
  std::lock_guard<std::mutex> lock(marker_mutex);
  size_t left = 0, right = 0;
  for (const auto& m : markers.markers) {
    (m.ns == "left" ? left : right) += 1;
    EXPECT_EQ(m.header.frame_id, "tanker");
    EXPECT_FALSE(m.points.empty());
    EXPECT_EQ(m.points.size() % 3, 0u);
  }
  EXPECT_EQ(left, 12u);
  EXPECT_EQ(right, 12u);

  // Bad clouds pass through with their stamps; the node answers the next good one.
  auto bad = ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), ros::Time::now());
  bad.data.resize(bad.data.size() / 2);  // ragged
  graph.cloud_pub().publish(bad);
  EXPECT_TRUE(out.Await(bad.header.stamp));
  auto nan = ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), ros::Time::now());
  const float q = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < nan.width; ++i) std::memcpy(&nan.data[16 * i], &q, 4);
  graph.cloud_pub().publish(nan);
  EXPECT_TRUE(out.Await(nan.header.stamp));
  EXPECT_EQ(out.filtered.by_stamp.at(nan.header.stamp)->width, 0u);  // nothing finite
  // Finite but absurd coordinates (every 10th point at z = 1e20, every 10th after it at 3e38)
  // once aborted the node inside Embree: now they are dropped and the rest culled.
  auto huge = ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), ros::Time::now());
  size_t absurd = 0;
  for (size_t i = 0; i + 1 < huge.width; i += 10, absurd += 2) {
    const float z[2] = {1e20f, 3e38f};
    std::memcpy(&huge.data[16 * i + 8], &z[0], 4);
    std::memcpy(&huge.data[16 * (i + 1) + 8], &z[1], 4);
  }
  graph.cloud_pub().publish(huge);
  ASSERT_TRUE(out.Await(huge.header.stamp));
  EXPECT_EQ(out.filtered.by_stamp.at(huge.header.stamp)->width +
                out.boom.by_stamp.at(huge.header.stamp)->width,
            scene.points.size() - absurd);
  EXPECT_GT(out.boom.by_stamp.at(huge.header.stamp)->width, removed.size() * 3 / 4);
  const ros::Time last = ros::Time::now();
  graph.cloud_pub().publish(ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), last));
  ASSERT_TRUE(out.Await(last));
  EXPECT_EQ(out.boom.by_stamp.at(last)->width, removed.size());
}

// A refused boom model or missing link tf: every frame passes through unculled and the
// diagnostics name the link.
void ExpectPassThrough(bool joint_states, const std::string& needle) {
  ros::NodeHandle nh;
  Graph graph(joint_states);
  Outputs out(nh);
  ASSERT_TRUE(WaitFor([&] { return graph.cloud_pub().getNumSubscribers() > 0; }, 30.0));
  ASSERT_TRUE(out.Connected());
  const Scene scene = MakeScene(graph.rig().T_tanker_left_optical.translation());
  const ros::Time stamp = ros::Time::now();
  graph.cloud_pub().publish(ToCloud(scene, graph.rig().T_tanker_left_optical.inverse(), stamp));
  ASSERT_TRUE(out.Await(stamp));
  EXPECT_EQ(out.filtered.by_stamp.at(stamp)->width, scene.points.size());
  EXPECT_EQ(out.boom.by_stamp.at(stamp)->width, 0u);
  ASSERT_TRUE(WaitFor(
      [&] {
        std::lock_guard<std::mutex> lock(out.diagnostics.mutex);
        return out.diagnostics.level == diagnostic_msgs::DiagnosticStatus::ERROR;
      },
      10.0));
  std::lock_guard<std::mutex> lock(out.diagnostics.mutex);
  std::printf("[ occlusion ] diagnostics: %s\n", out.diagnostics.message.c_str());
  EXPECT_NE(out.diagnostics.message.find("unculled"), std::string::npos);
  EXPECT_NE(out.diagnostics.message.find(needle), std::string::npos);
}

TEST(BadInput, LinkWithoutCollisionGeometry) {
  ExpectPassThrough(true, "boom link 'fairing' has visual but no collision geometry");
}

TEST(BadInput, MissingLinkTf) { ExpectPassThrough(false, "no tf tanker -> '"); }

}  // namespace
