#include "aar_registration/ros/registration_node.h"

#include <chrono>
#include <cstring>
#include <set>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_msgs/PoseEstimate.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/package.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>

namespace aar_registration {
namespace {

// Finite x, y, z of a cloud; throws std::invalid_argument if it has no float32 x, y, z.
std::vector<Eigen::Vector3d> FromCloud(const sensor_msgs::PointCloud2& msg) {
  for (const char* name : {"x", "y", "z"}) {
    bool found = false;
    for (const auto& f : msg.fields)
      found |= f.name == name && f.datatype == sensor_msgs::PointField::FLOAT32;
    if (!found)
      throw std::invalid_argument(std::string("cloud has no float32 field '") + name + "'");
  }
  // The layout must hold together before any byte is read.
  uint32_t offsets[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    for (const auto& f : msg.fields) {
      if (f.name == std::string(1, "xyz"[k])) offsets[k] = f.offset;
    }
    if (offsets[k] + 4 > msg.point_step)
      throw std::invalid_argument("cloud field offsets exceed point_step");
  }
  if (msg.row_step < static_cast<uint64_t>(msg.width) * msg.point_step ||
      msg.data.size() != static_cast<size_t>(msg.row_step) * msg.height) {
    throw std::invalid_argument("cloud is malformed: " + std::to_string(msg.data.size()) +
                                " bytes for " + std::to_string(msg.height) + " rows of " +
                                std::to_string(msg.row_step) + " (" + std::to_string(msg.width) +
                                " points of " + std::to_string(msg.point_step) + ")");
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>(msg.width) * msg.height);
  for (uint32_t row = 0; row < msg.height; ++row) {
    for (uint32_t col = 0; col < msg.width; ++col) {
      const uint8_t* point = &msg.data[static_cast<size_t>(row) * msg.row_step +
                                       static_cast<size_t>(col) * msg.point_step];
      float v[3];
      for (int k = 0; k < 3; ++k) std::memcpy(&v[k], point + offsets[k], sizeof(float));
      if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))
        points.emplace_back(v[0], v[1], v[2]);
    }
  }
  return points;
}

// Waits for a transform in wall-clock time. tf2's own timed wait counts simulated time, which
// stands still in lockstep while the simulator waits for this node.
bool WaitForTransform(const tf2_ros::Buffer& buffer, const std::string& target,
                      const std::string& source, const ros::Time& time, double timeout_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!buffer.canTransform(target, source, time)) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return false;
    ros::WallDuration(0.005).sleep();
  }
  return true;
}

template <typename T>
T Param(const ros::NodeHandle& nh, const std::string& name, const T& fallback,
        std::set<std::string>& known) {
  known.insert(name);
  T value = fallback;
  if (nh.hasParam(name) && !nh.getParam(name, value)) {
    throw std::invalid_argument("parameter " + nh.resolveName(name) + " has the wrong type");
  }
  return value;
}

}  // namespace

RegistrationNodeOptions LoadRegistrationNodeOptions(const ros::NodeHandle& nh) {
  RegistrationNodeOptions o;
  std::set<std::string> known;
  const std::string reference = Param<std::string>(nh, "reference", "shelled", known);
  if (reference == "shelled")
    o.reference = ReferenceKind::kShelled;
  else if (reference == "wings_nose")
    o.reference = ReferenceKind::kWingsNose;
  else if (reference == "dense")
    o.reference = ReferenceKind::kDense;
  else if (reference == "topic")
    o.reference = ReferenceKind::kTopic;
  else
    throw std::invalid_argument("~reference must be shelled, wings_nose, dense or topic, not '" +
                                reference + "'");
  o.receiver_mesh = Param<std::string>(
      nh, "receiver_mesh", ros::package::getPath("aar_sim") + "/models/receiver.obj", known);
  o.sampling.points_per_m2 = Param(nh, "sample_density", o.sampling.points_per_m2, known);
  o.sampling.seed = static_cast<uint64_t>(Param(nh, "sample_seed", 1, known));
  o.sampling.visibility_tolerance =
      Param(nh, "visibility_tolerance", o.sampling.visibility_tolerance, known);
  // Nominal pose for shelling: the default approach's contact pose.
  const Eigen::Vector3d nominal(Param(nh, "nominal_x", -35.0, known),
                                Param(nh, "nominal_y", 0.0, known),
                                Param(nh, "nominal_z", -10.19, known));
  const aar_geometry::RollPitchYaw nominal_rpy{
      aar_geometry::DegToRad(Param(nh, "nominal_roll_deg", 0.0, known)),
      aar_geometry::DegToRad(Param(nh, "nominal_pitch_deg", -2.0, known)),
      aar_geometry::DegToRad(Param(nh, "nominal_yaw_deg", 0.0, known))};
  o.T_tanker_receiver_nominal = aar_geometry::MakeTransform(nominal, nominal_rpy);
  const std::string metric = Param<std::string>(nh, "icp_metric", "point_to_point", known);
  if (metric == "point_to_point")
    o.icp.metric = IcpMetric::kPointToPoint;
  else if (metric == "point_to_plane")
    o.icp.metric = IcpMetric::kPointToPlane;
  else if (metric == "generalized_pcl")
    o.icp.metric = IcpMetric::kGeneralizedPcl;
  else
    throw std::invalid_argument(
        "~icp_metric must be point_to_point, point_to_plane or generalized_pcl, not '" + metric +
        "'");
  o.icp.max_iterations = Param(nh, "max_iterations", o.icp.max_iterations, known);
  o.icp.max_correspondence_distance =
      Param(nh, "max_correspondence_distance", o.icp.max_correspondence_distance, known);
  o.icp.min_rms_improvement = Param(nh, "min_rms_improvement", o.icp.min_rms_improvement, known);
  o.icp.rms_epsilon = Param(nh, "rms_epsilon", o.icp.rms_epsilon, known);
  const std::string seed = Param<std::string>(nh, "seed", "centroid", known);
  if (seed == "centroid")
    o.seed = SeedMode::kCentroid;
  else if (seed == "previous")
    o.seed = SeedMode::kPrevious;
  else
    throw std::invalid_argument("~seed must be centroid or previous, not '" + seed + "'");
  o.previous_max_age = Param(nh, "previous_max_age", o.previous_max_age, known);
  o.tanker_frame = Param(nh, "tanker_frame", o.tanker_frame, known);
  o.receiver_frame = Param(nh, "receiver_frame", o.receiver_frame, known);
  o.left_camera_frame = Param(nh, "left_camera_frame", o.left_camera_frame, known);
  o.right_camera_frame = Param(nh, "right_camera_frame", o.right_camera_frame, known);
  o.tf_timeout = Param(nh, "tf_timeout", o.tf_timeout, known);

  std::vector<std::string> names;
  nh.getParamNames(names);
  const std::string prefix = nh.getNamespace() + "/";
  for (const auto& name : names) {
    if (name.rfind(prefix, 0) == 0 && !known.count(name.substr(prefix.size()))) {
      throw std::invalid_argument("unknown parameter " + name + " (misspelt?)");
    }
  }
  return o;
}

RegistrationNode::RegistrationNode(ros::NodeHandle nh, ros::NodeHandle,
                                   const RegistrationNodeOptions& options)
    : nh_(nh), options_(options), tf_listener_(tf_buffer_), icp_(options.icp) {
  pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("aar/receiver_pose", 10);
  estimate_pub_ = nh_.advertise<aar_msgs::PoseEstimate>("aar/pose_estimate", 10);
  if (options_.reference == ReferenceKind::kTopic) {
    reference_sub_ = nh_.subscribe("aar/reference_cloud", 2, &RegistrationNode::OnReference, this);
  } else {
    BuildStaticReference();
  }
  cloud_sub_ = nh_.subscribe("points", 2, &RegistrationNode::OnCloud, this);
}

RegistrationNode::~RegistrationNode() {
  cloud_sub_.shutdown();
  reference_sub_.shutdown();
}

void RegistrationNode::BuildStaticReference() {
  const auto start = std::chrono::steady_clock::now();
  const aar_geometry::TriangleMesh mesh = aar_geometry::LoadMesh(options_.receiver_mesh);
  ReferenceCloud cloud = SampleReceiver(mesh, options_.sampling);
  if (options_.reference != ReferenceKind::kDense) {
    // Shelled as the cameras see the receiver at the nominal pose: their positions from tf.
    std::vector<Eigen::Vector3d> eyes;
    for (const auto& frame : {options_.left_camera_frame, options_.right_camera_frame}) {
      if (!WaitForTransform(tf_buffer_, options_.tanker_frame, frame, ros::Time(0), 10.0)) {
        throw std::runtime_error("no tf " + options_.tanker_frame + " -> " + frame +
                                 " within 10 s, needed to shell the reference model");
      }
      const Eigen::Isometry3d T_tanker_camera = tf2::transformToEigen(
          tf_buffer_.lookupTransform(options_.tanker_frame, frame, ros::Time(0)).transform);
      eyes.push_back(options_.T_tanker_receiver_nominal.inverse() * T_tanker_camera.translation());
    }
    cloud = Shell(cloud, VisibilityTester(mesh), eyes, options_.sampling.visibility_tolerance);
    if (options_.reference == ReferenceKind::kWingsNose)
      cloud = cloud.Select({"left_wing", "right_wing", "nose"});
  }
  if (cloud.size() < 100)
    throw std::runtime_error("reference model has only " + std::to_string(cloud.size()) +
                             " points");
  reference_points_ = cloud.points;
  icp_.SetTarget(cloud.points, cloud.normals);
  ROS_INFO_STREAM("registration: reference model of "
                  << cloud.size() << " points built in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
                  << " s");
}

void RegistrationNode::OnReference(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  try {
    std::vector<Eigen::Vector3d> points = FromCloud(*msg);
    if (points.size() < 10)
      throw std::invalid_argument("reference cloud has " + std::to_string(points.size()) +
                                  " points");
    std::lock_guard<std::mutex> lock(mutex_);
    icp_.SetTarget(points);  // point-to-plane needs normals: topic references give none yet
    reference_points_ = std::move(points);
  } catch (const std::exception& e) {
    ReportError(std::string("reference cloud rejected: ") + e.what());
  }
}

void RegistrationNode::ReportError(const std::string& what) {
  std::lock_guard<std::mutex> lock(report_mutex_);
  const ros::WallTime now = ros::WallTime::now();
  ros::WallTime& last = last_reported_[what];
  if (last.isZero() || now - last > ros::WallDuration(5.0)) {
    last = now;
    ROS_ERROR_STREAM("registration: " << what);
  }
}

void RegistrationNode::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  const auto received = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    if (!icp_.has_target()) throw std::runtime_error("no reference model yet");
    if (!WaitForTransform(tf_buffer_, options_.tanker_frame, msg->header.frame_id,
                          msg->header.stamp, options_.tf_timeout)) {
      throw std::runtime_error("no tf " + options_.tanker_frame + " -> '" + msg->header.frame_id +
                               "' at the cloud's stamp within " +
                               std::to_string(options_.tf_timeout) + " s");
    }
    const Eigen::Isometry3d T_tanker_cloud = tf2::transformToEigen(
        tf_buffer_.lookupTransform(options_.tanker_frame, msg->header.frame_id, msg->header.stamp));
    std::vector<Eigen::Vector3d> sensed = FromCloud(*msg);
    if (sensed.size() < static_cast<size_t>(options_.icp.min_correspondences)) {
      throw std::invalid_argument("cloud has " + std::to_string(sensed.size()) +
                                  " finite points, too few to register");
    }
    for (auto& p : sensed) p = T_tanker_cloud * p;

    Eigen::Isometry3d seed = CentroidSeed(sensed, reference_points_);  // T_tanker_receiver
    if (options_.seed == SeedMode::kPrevious && previous_ &&
        (msg->header.stamp - previous_->first).toSec() <= options_.previous_max_age &&
        msg->header.stamp >= previous_->first) {
      seed = previous_->second;
    }
    const auto start = std::chrono::steady_clock::now();
    const RegistrationResult r = icp_.Align(sensed, seed.inverse());
    const double registration_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (r.correspondences < options_.icp.min_correspondences) {
      throw std::runtime_error("only " + std::to_string(r.correspondences) + " of " +
                               std::to_string(sensed.size()) + " points within " +
                               std::to_string(options_.icp.max_correspondence_distance) +
                               " m of the reference: no pose");
    }
    const Eigen::Isometry3d T_tanker_receiver = r.T_target_source.inverse();
    if (!T_tanker_receiver.matrix().allFinite())
      throw std::runtime_error("registration gave a non-finite pose");
    if (r.converged) previous_ = std::make_pair(msg->header.stamp, T_tanker_receiver);

    std_msgs::Header header;
    header.stamp = msg->header.stamp;
    header.frame_id = options_.tanker_frame;
    aar_msgs::PoseEstimate estimate;
    estimate.header = header;
    estimate.valid = true;
    estimate.pose = tf2::toMsg(T_tanker_receiver);
    estimate.converged = r.converged;
    estimate.iterations = static_cast<uint32_t>(r.iterations);
    estimate.rms = r.rms;
    estimate.fitness = r.fitness;
    estimate.sensed_points = static_cast<uint32_t>(sensed.size());
    estimate.reference_points = static_cast<uint32_t>(reference_points_.size());
    estimate.registration_ms = registration_ms;
    estimate.total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - received)
            .count();
    geometry_msgs::PoseWithCovarianceStamped pose;  // covariance not estimated: zeros
    pose.header = header;
    pose.pose.pose = estimate.pose;
    geometry_msgs::TransformStamped tf = tf2::eigenToTransform(T_tanker_receiver);
    tf.header = header;
    tf.child_frame_id = options_.receiver_frame;
    tf_broadcaster_.sendTransform(tf);
    pose_pub_.publish(pose);
    estimate_pub_.publish(estimate);
    ROS_DEBUG_STREAM("registration: " << msg->header.stamp << ": " << r.iterations
                                      << " iterations, rms " << r.rms << " m, " << registration_ms
                                      << " ms" << (r.converged ? "" : " (not converged)"));
  } catch (const std::exception& e) {
    ReportError(std::string("cloud not registered, no estimate for this frame: ") + e.what());
    aar_msgs::PoseEstimate none;  // valid = false: a miss, and lockstep moves on
    none.header.stamp = msg->header.stamp;
    none.header.frame_id = options_.tanker_frame;
    none.pose.orientation.w = 1.0;
    none.total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - received)
            .count();
    estimate_pub_.publish(none);
  }
}

}  // namespace aar_registration
