#include "aar_registration/ros/registration_node.h"

#include "aar_registration/ros/conversions.h"
#include "aar_registration/ros/node_utils.h"

#include <chrono>
#include <cstring>
#include <filesystem>
#include <set>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_msgs/PoseEstimate.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/package.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

namespace aar_registration {

RegistrationNodeOptions LoadRegistrationNodeOptions(const ros::NodeHandle& nh) {
  RegistrationNodeOptions o;
  ParamReader params(nh);
  const std::string reference = params.Get<std::string>("reference", "shelled");
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
  o.receiver_mesh = params.Get<std::string>(
      "receiver_mesh", ros::package::getPath("aar_sim") + "/models/receiver.obj");
  o.sampling.points_per_m2 = params.Get("sample_density", o.sampling.points_per_m2);
  o.sampling.seed = static_cast<uint64_t>(params.Get("sample_seed", 1));
  o.sampling.visibility_tolerance =
      params.Get("visibility_tolerance", o.sampling.visibility_tolerance);
  // Nominal pose for shelling: the default approach's contact pose.
  const Eigen::Vector3d nominal(params.Get("nominal_x", -35.0), params.Get("nominal_y", 0.0),
                                params.Get("nominal_z", -10.19));
  const aar_geometry::RollPitchYaw nominal_rpy{
      aar_geometry::DegToRad(params.Get("nominal_roll_deg", 0.0)),
      aar_geometry::DegToRad(params.Get("nominal_pitch_deg", -2.0)),
      aar_geometry::DegToRad(params.Get("nominal_yaw_deg", 0.0))};
  o.T_tanker_receiver_nominal = aar_geometry::MakeTransform(nominal, nominal_rpy);
  const std::string metric = params.Get<std::string>("icp_metric", "point_to_point");
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
  o.icp.max_iterations = params.Get("max_iterations", o.icp.max_iterations);
  o.icp.max_correspondence_distance =
      params.Get("max_correspondence_distance", o.icp.max_correspondence_distance);
  o.icp.min_rms_improvement = params.Get("min_rms_improvement", o.icp.min_rms_improvement);
  o.icp.rms_epsilon = params.Get("rms_epsilon", o.icp.rms_epsilon);
  const std::string seed = params.Get<std::string>("seed", "centroid");
  if (seed == "centroid")
    o.seed = SeedMode::kCentroid;
  else if (seed == "previous")
    o.seed = SeedMode::kPrevious;
  else
    throw std::invalid_argument("~seed must be centroid or previous, not '" + seed + "'");
  o.previous_max_age = params.Get("previous_max_age", o.previous_max_age);
  o.tanker_frame = params.Get("tanker_frame", o.tanker_frame);
  o.receiver_frame = params.Get("receiver_frame", o.receiver_frame);
  o.truth_frame = params.Get("truth_frame", o.truth_frame);
  o.left_camera_frame = params.Get("left_camera_frame", o.left_camera_frame);
  o.right_camera_frame = params.Get("right_camera_frame", o.right_camera_frame);
  o.tf_timeout = params.Get("tf_timeout", o.tf_timeout);
  o.reference_timeout = params.Get("reference_timeout", o.reference_timeout);

  params.RejectUnknown();
  return o;
}

RegistrationNode::RegistrationNode(ros::NodeHandle nh, ros::NodeHandle,
                                   const RegistrationNodeOptions& options)
    : nh_(nh), options_(options), tf_listener_(tf_buffer_), icp_(options.icp) {
  pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("aar/receiver_pose", 10);
  estimate_pub_ = nh_.advertise<aar_msgs::PoseEstimate>("aar/pose_estimate", 10);
  PublishModels();
  if (options_.reference == ReferenceKind::kTopic) {
    // Each cloud is registered to the reference built for its own frame (same stamp).
    points_filter_.subscribe(nh_, "points", 5);
    reference_filter_.subscribe(nh_, "aar/reference_cloud", 5);
    sync_ = std::make_unique<Sync>(points_filter_, reference_filter_, 10);
    sync_->registerCallback(&RegistrationNode::OnPair, this);
    // A cloud whose reference never comes still gets an answer (an invalid estimate), so that
    // lockstep moves on and the log says what is missing.
    cloud_sub_ = nh_.subscribe("points", 5, &RegistrationNode::OnPointsSeen, this);
    pending_timer_ =
        nh_.createWallTimer(ros::WallDuration(0.1), &RegistrationNode::ExpirePending, this);
  } else {
    BuildStaticReference();
    cloud_sub_ = nh_.subscribe("points", 2, &RegistrationNode::OnCloud, this);
  }
}

RegistrationNode::~RegistrationNode() {
  pending_timer_.stop();
  cloud_sub_.shutdown();
  points_filter_.unsubscribe();
  reference_filter_.unsubscribe();
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

void RegistrationNode::SetReference(const sensor_msgs::PointCloud2& msg) {
  const CloudPoints cloud = FromCloud(msg);
  std::vector<uint32_t> keep;  // the points both cameras see (class 0) when classes are given
  if (HasField(msg, "visibility")) {
    const std::vector<double> classes = ReadField(msg, "visibility", cloud.indices);
    for (size_t i = 0; i < classes.size(); ++i) {
      if (classes[i] == 0.0) keep.push_back(static_cast<uint32_t>(i));
    }
  } else {
    for (uint32_t i = 0; i < cloud.points.size(); ++i) keep.push_back(i);
  }
  if (keep.size() < 10) {
    throw std::invalid_argument("reference cloud has " + std::to_string(keep.size()) +
                                " usable points");
  }
  std::vector<Eigen::Vector3d> points, normals;
  for (const uint32_t i : keep) points.push_back(cloud.points[i]);
  if (HasField(msg, "normal_x")) {
    std::vector<uint32_t> at;
    for (const uint32_t i : keep) at.push_back(cloud.indices[i]);
    const auto nx = ReadField(msg, "normal_x", at), ny = ReadField(msg, "normal_y", at),
               nz = ReadField(msg, "normal_z", at);
    for (size_t i = 0; i < at.size(); ++i) normals.emplace_back(nx[i], ny[i], nz[i]);
    icp_.SetTarget(points, normals);
  } else {
    icp_.SetTarget(points);  // point-to-plane needs normals: it refuses such a target
  }
  reference_points_ = std::move(points);
}

void RegistrationNode::OnPointsSeen(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(pending_mutex_);
  if (!answered_.count(msg->header.stamp)) pending_[msg->header.stamp] = ros::WallTime::now();
}

void RegistrationNode::ExpirePending(const ros::WallTimerEvent&) {
  std::vector<ros::Time> expired;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    const ros::WallTime now = ros::WallTime::now();
    for (auto it = pending_.begin(); it != pending_.end();) {
      if ((now - it->second).toSec() > options_.reference_timeout) {
        expired.push_back(it->first);
        answered_.insert(it->first);
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
    while (answered_.size() > 100) answered_.erase(answered_.begin());
  }
  for (const ros::Time& stamp : expired) {
    ReportError("no reference cloud with the points' stamp within " +
                std::to_string(options_.reference_timeout) +
                " s: is occlusion_node publishing aar/reference_cloud (publish_reference)?");
    PublishNone(stamp, 0.0);
  }
}

void RegistrationNode::OnPair(const sensor_msgs::PointCloud2::ConstPtr& points,
                              const sensor_msgs::PointCloud2::ConstPtr& reference) {
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    if (answered_.count(points->header.stamp)) return;  // already answered as expired
    answered_.insert(points->header.stamp);
    pending_.erase(points->header.stamp);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  try {
    SetReference(*reference);
  } catch (const std::exception& e) {
    icp_ = Icp(options_.icp);  // no stale target: this frame gets no estimate
    reference_points_.clear();
    ReportError(std::string("reference cloud rejected: ") + e.what());
  }
  Register(points);
}

void RegistrationNode::ReportError(const std::string& what) {
  if (errors_.ShouldLog(what)) ROS_ERROR_STREAM("registration: " << what);
}

void RegistrationNode::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  Register(msg);
}

void RegistrationNode::Register(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  const auto received = std::chrono::steady_clock::now();
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
    std::vector<Eigen::Vector3d> sensed = FromCloud(*msg).points;
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
    PublishNone(msg->header.stamp, std::chrono::duration<double, std::milli>(
                                       std::chrono::steady_clock::now() - received)
                                       .count());
  }
}

void RegistrationNode::PublishModels() {
  // The receiver model at the estimate (orange) and at truth (grey), for rviz: latched, each
  // locked to its frame, shown where tf has that frame (truth: simulations and their bags).
  models_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("aar/receiver_models", 1, true);
  visualization_msgs::MarkerArray models;
  for (const auto& [frame, ns] : {std::make_pair(options_.receiver_frame, "estimate"),
                                  std::make_pair(options_.truth_frame, "truth")}) {
    visualization_msgs::Marker m;
    m.header.frame_id = frame;
    m.ns = ns;
    m.type = visualization_msgs::Marker::MESH_RESOURCE;
    m.mesh_resource = "file://" + std::filesystem::absolute(options_.receiver_mesh).string();
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 1.0;
    const bool estimate = std::string(ns) == "estimate";
    m.color.r = estimate ? 1.0f : 0.8f;
    m.color.g = estimate ? 0.55f : 0.8f;
    m.color.b = estimate ? 0.1f : 0.8f;
    m.color.a = estimate ? 0.6f : 1.0f;
    m.frame_locked = true;
    models.markers.push_back(m);
  }
  models_pub_.publish(models);
}

void RegistrationNode::PublishNone(const ros::Time& stamp, double total_ms) {
  aar_msgs::PoseEstimate none;  // valid = false: a miss, and lockstep moves on
  none.header.stamp = stamp;
  none.header.frame_id = options_.tanker_frame;
  none.pose.orientation.w = 1.0;
  none.total_ms = total_ms;
  estimate_pub_.publish(none);
}

}  // namespace aar_registration
