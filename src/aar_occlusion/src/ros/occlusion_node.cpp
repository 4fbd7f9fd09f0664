#include "aar_occlusion/ros/occlusion_node.h"

#include <chrono>

#include <boost/make_shared.hpp>

#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_registration/icp.h>
#include <aar_registration/ros/conversions.h>
#include <aar_registration/ros/node_utils.h>
#include <ros/package.h>
#include <tf2_eigen/tf2_eigen.h>

#include "aar_occlusion/ros/conversions.h"

namespace aar_occlusion {

using aar_registration::WaitForTransform;

OcclusionNodeOptions LoadOcclusionNodeOptions(const ros::NodeHandle& nh) {
  OcclusionNodeOptions o;
  aar_registration::ParamReader params(nh);
  o.cull = ParseCullMethod(params.Get<std::string>("cull", ToString(o.cull)));
  o.parts.cull_margin = params.Get("cull_margin", o.parts.cull_margin);
  o.parts.silhouette_margin = params.Get("silhouette_margin", o.parts.silhouette_margin);
  if (!(o.parts.cull_margin >= 0.0) || !(o.parts.silhouette_margin >= 0.0))
    throw std::invalid_argument("~cull_margin and ~silhouette_margin must be >= 0");
  o.boom.cull_behind_boom = params.Get("cull_behind_boom", o.boom.cull_behind_boom);
  o.publish_reference = params.Get("publish_reference", o.publish_reference);
  o.robot_description = params.Get("robot_description", o.robot_description);
  o.receiver_mesh = params.Get<std::string>(
      "receiver_mesh", ros::package::getPath("aar_sim") + "/models/receiver.obj");
  o.sampling.points_per_m2 = params.Get("sample_density", o.sampling.points_per_m2);
  o.sampling.seed = static_cast<uint64_t>(params.Get("sample_seed", 1));
  o.reference.visibility_tolerance =
      params.Get("visibility_tolerance", o.reference.visibility_tolerance);
  o.reference.reshell_distance = params.Get("reshell_distance", o.reference.reshell_distance);
  o.tanker_frame = params.Get("tanker_frame", o.tanker_frame);
  o.receiver_frame = params.Get("receiver_frame", o.receiver_frame);
  o.left_camera_frame = params.Get("left_camera_frame", o.left_camera_frame);
  o.right_camera_frame = params.Get("right_camera_frame", o.right_camera_frame);
  o.tf_timeout = params.Get("tf_timeout", o.tf_timeout);
  o.estimate_max_age = params.Get("estimate_max_age", o.estimate_max_age);
  o.marker_length = params.Get("marker_length", o.marker_length);
  o.estimate_wait = params.Get("estimate_wait", o.estimate_wait);
  o.diagnostic_period = params.Get("diagnostic_period", o.diagnostic_period);
  if (!(o.diagnostic_period > 0.0)) throw std::invalid_argument("~diagnostic_period must be > 0");
  params.RejectUnknown();
  return o;
}

OcclusionNode::OcclusionNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                             const OcclusionNodeOptions& options)
    : nh_(nh), options_(options), tf_listener_(tf_buffer_), diagnostics_(nh, private_nh) {
  // The boom: a refused model is reported and every frame passes through unculled.
  std::string urdf;
  if (!nh_.getParam(options_.robot_description, urdf)) {
    boom_error_ = "no boom URDF in parameter " + nh_.resolveName(options_.robot_description);
  } else {
    try {
      boom_ = std::make_unique<BoomOcclusion>(
          LoadBoomParts(
              aar_geometry::ParseRobotModel(urdf, nh_.resolveName(options_.robot_description), ""),
              options_.parts),
          options_.boom);
    } catch (const std::exception& e) {
      boom_error_ = e.what();
    }
  }
  if (!boom_error_.empty())
    ROS_ERROR_STREAM(
        "occlusion: boom model refused, clouds pass through unculled: " << boom_error_);

  if (options_.publish_reference) {
    const auto mesh = aar_geometry::LoadMesh(options_.receiver_mesh);  // throws: fatal
    reference_ = std::make_unique<DynamicReference>(
        aar_registration::SampleReceiver(mesh, options_.sampling), mesh, options_.reference);
  }
  filtered_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/points_filtered", 5);
  boom_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/boom_points", 5);
  if (options_.publish_reference)
    reference_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/reference_cloud", 5);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("aar/shadow_volumes", 2, true);
  diagnostics_.setHardwareID("boom occlusion");
  diagnostics_.add("occlusion", this, &OcclusionNode::Diagnose);
  // Wall time: simulated time stands still in lockstep, and the status matters most then.
  diagnostics_timer_ = nh_.createWallTimer(
      ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnostics_.force_update(); });
  cloud_sub_ = nh_.subscribe("points", 5, &OcclusionNode::OnCloud, this);
  ROS_INFO_STREAM("occlusion: culling " << ToString(options_.cull) << ", "
                                        << (boom_ ? boom_->parts().size() : 0) << " boom parts, "
                                        << (reference_ ? reference_->size() : 0)
                                        << " reference samples");
}

OcclusionNode::~OcclusionNode() {
  diagnostics_timer_.stop();  // it reads members destroyed before it
  cloud_sub_.shutdown();
}

std::optional<Eigen::Isometry3d> OcclusionNode::Lookup(const std::string& frame,
                                                       const ros::Time& stamp, std::string* error) {
  if (!WaitForTransform(tf_buffer_, options_.tanker_frame, frame, stamp, options_.tf_timeout)) {
    *error = "no tf " + options_.tanker_frame + " -> '" + frame + "' at the cloud's stamp within " +
             std::to_string(options_.tf_timeout) + " s";
    return std::nullopt;
  }
  return tf2::transformToEigen(tf_buffer_.lookupTransform(options_.tanker_frame, frame, stamp));
}

void OcclusionNode::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  const auto start = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  std::string error;                                  // why this frame is not culled
  std::string reference_error;                        // why it has no reference
  sensor_msgs::PointCloud2::ConstPtr filtered = msg;  // passed through unless culled below
  sensor_msgs::PointCloud2 boom_points;
  boom_points.header = msg->header;
  boom_points.fields = msg->fields;
  boom_points.point_step = msg->point_step;
  boom_points.height = 1;
  std_msgs::Header reference_header = msg->header;
  reference_header.frame_id = options_.receiver_frame;
  DynamicReferenceResult reference;  // empty: registration gets no target and skips the frame

  try {
    const aar_registration::CloudPoints cloud = aar_registration::FromCloud(*msg);
    const auto T_tanker_cloud = Lookup(msg->header.frame_id, msg->header.stamp, &error);
    const auto T_left = Lookup(options_.left_camera_frame, msg->header.stamp, &error);
    const auto T_right = Lookup(options_.right_camera_frame, msg->header.stamp, &error);
    if (!T_tanker_cloud || !T_left || !T_right) throw std::runtime_error(error);
    std::vector<Eigen::Vector3d> points = cloud.points;
    for (auto& p : points) p = *T_tanker_cloud * p;

    // Place the boom; without it this frame passes through unculled.
    bool placed = false;
    const bool needed =
        options_.cull != CullMethod::kNone || reference_ || markers_pub_.getNumSubscribers() > 0;
    if (!needed) {
      // Nothing to do with the boom: the cloud passes through as configured.
    } else if (!boom_) {
      error = boom_error_;
    } else {
      std::map<std::string, Eigen::Isometry3d> links;
      for (const auto& link : boom_->links()) {
        if (auto T = Lookup(link, msg->header.stamp, &error)) links[link] = *T;
      }
      if (links.size() == boom_->links().size()) {
        try {
          markers_stale_ |= boom_->Update(links, T_left->translation(), T_right->translation());
          placed = true;
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
    }
    if (placed) error.clear();

    std::vector<bool> is_boom(points.size(), false);
    if (placed) is_boom = boom_->Cull(points, options_.cull);
    std::vector<uint32_t> keep, removed;
    std::vector<Eigen::Vector3d> kept_points;
    for (size_t i = 0; i < points.size(); ++i) {
      (is_boom[i] ? removed : keep).push_back(cloud.indices[i]);
      if (!is_boom[i]) kept_points.push_back(points[i]);
    }
    filtered = boost::make_shared<const sensor_msgs::PointCloud2>(
        aar_registration::SelectPoints(*msg, keep));
    boom_points = aar_registration::SelectPoints(*msg, removed);

    if (reference_) {
      // Predicted pose: the latest estimate, else the thesis seed (centroid, tanker orientation).
      std::optional<Eigen::Isometry3d> T_tanker_receiver;
      if (previous_stamp_) {  // the estimate of the previous cloud, usually on its way
        WaitForTransform(tf_buffer_, options_.tanker_frame, options_.receiver_frame,
                         *previous_stamp_, options_.estimate_wait);
      }
      if (tf_buffer_.canTransform(options_.tanker_frame, options_.receiver_frame, ros::Time(0))) {
        const auto latest = tf_buffer_.lookupTransform(options_.tanker_frame,
                                                       options_.receiver_frame, ros::Time(0));
        const double age = (msg->header.stamp - latest.header.stamp).toSec();
        if (age >= 0.0 && age <= options_.estimate_max_age)
          T_tanker_receiver = tf2::transformToEigen(latest);
      }
      if (!T_tanker_receiver && !kept_points.empty()) {
        T_tanker_receiver = aar_registration::CentroidSeed(kept_points, {Eigen::Vector3d::Zero()});
      }
      try {
        if (!T_tanker_receiver)
          throw std::runtime_error("no predicted pose: no estimate, no points");
        reference = placed ? reference_->Build(*T_tanker_receiver, *boom_)
                           : reference_->Build(*T_tanker_receiver, T_left->translation(),
                                               T_right->translation());
      } catch (const std::exception& e) {
        reference_error = e.what();
        reference = DynamicReferenceResult{};
      }
    }
    if (placed && markers_stale_ && markers_pub_.getNumSubscribers() > 0) {
      markers_pub_.publish(ShadowMarkers(
          *boom_,
          [&] {
            std_msgs::Header h = msg->header;
            h.frame_id = options_.tanker_frame;
            return h;
          }(),
          options_.marker_length));
      markers_stale_ = false;
    }
  } catch (const std::exception& e) {
    error = e.what();
    if (reference_) reference_error = "no reference without the cloud: " + error;
  }
  if (!error.empty()) ReportError("frame passes through unculled: " + error);
  if (!reference_error.empty()) ReportError("empty reference for this frame: " + reference_error);
  previous_stamp_ = msg->header.stamp;

  filtered_pub_.publish(filtered);
  boom_pub_.publish(boom_points);
  if (reference_) reference_pub_.publish(ToCloud(reference, reference_header));
  {
    std::lock_guard<std::mutex> report(report_mutex_);
    ++frames_;
    unculled_frames_ += !error.empty();
    last_frame_error_ = error;
    last_reference_error_ = reference_error;
    reference_failures_ += !reference_error.empty();
    last_boom_points_ = boom_points.width;
    last_reference_both_ = reference.both;
    last_ms_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
}

void OcclusionNode::ReportError(const std::string& what) {
  if (errors_.ShouldLog(what)) ROS_ERROR_STREAM("occlusion: " << what);
}

void OcclusionNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(report_mutex_);
  status.add("frames", frames_);
  status.add("frames passed through unculled", unculled_frames_);
  status.add("frames without a reference", reference_failures_);
  status.add("cull method", ToString(options_.cull));
  status.add("boom points removed (last frame)", last_boom_points_);
  status.add("reference points seen by both cameras (last frame)", last_reference_both_);
  status.add("occlusion stage [ms] (last frame)", last_ms_);
  if (!boom_error_.empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "boom model refused, frames pass through unculled: " + boom_error_);
  } else if (!last_frame_error_.empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "last frame passed through unculled: " + last_frame_error_);
  } else if (!last_reference_error_.empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "last frame has no reference: " + last_reference_error_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, frames_ > 0 ? "culling" : "no input");
  }
}

}  // namespace aar_occlusion
