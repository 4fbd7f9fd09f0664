#include "aar_occlusion/ros/occlusion_node.h"

#include <chrono>

#include <boost/make_shared.hpp>

#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_ros_common/point_cloud.h>
#include <aar_ros_common/receiver_params.h>
#include <aar_ros_common/robot_description.h>
#include <aar_ros_common/start_count.h>
#include <aar_ros_common/tf_bridge.h>

#include "aar_occlusion/ros/conversions.h"

namespace aar_occlusion {

OcclusionNode::OcclusionNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                             const OcclusionNodeOptions& options)
    : nh_(nh),
      options_(options),
      tf_listener_(tf_buffer_),
      diagnostics_(nh, private_nh),
      ledger_(nh, "occlusion", options.common.rig) {
  // The boom: a refused model is reported and every frame passes through unculled.
  std::optional<aar_geometry::RobotModel> boom;
  std::string boom_error;
  if (!options_.step.model_boom) {
    ROS_INFO("occlusion: model_boom is false: no boom, nothing culled, self-occlusion only");
  } else {
    try {
      boom = aar_ros_common::LoadRobotDescription(nh_, options_.common.robot_description);
    } catch (const std::exception& e) {
      boom_error = e.what();
    }
  }
  std::optional<aar_geometry::TriangleMesh> receiver;
  if (options_.step.build_reference)
    receiver = aar_description::LoadReceiverMesh(options_.receiver);  // throws: fatal
  step_ = std::make_unique<OcclusionStep>(options_.step, boom, boom_error,
                                          receiver ? &*receiver : nullptr);
  if (!step_->boom_error().empty())
    ROS_ERROR_STREAM(
        "occlusion: boom model refused, clouds pass through unculled: " << step_->boom_error());

  filtered_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/points_filtered", 5);
  boom_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/boom_points", 5);
  if (step_->builds_reference())
    reference_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("aar/reference_cloud", 5);
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("aar/shadow_volumes", 2, true);
  if (options_.step.cull_propellers && options_.step.propellers.empty()) {
    ROS_WARN_STREAM("occlusion: cull_propellers is on, but the receiver description "
                    << options_.receiver.path << " lists no propellers: nothing to cull");
  }
  diagnostics_.setHardwareID("boom occlusion");
  diagnostics_.add("occlusion", this, &OcclusionNode::Diagnose);
  // Wall time: simulated time stands still in lockstep, and the status matters most then.
  diagnostics_timer_ =
      nh_.createWallTimer(ros::WallDuration(options_.common.diagnostic_period),
                          [this](const ros::WallTimerEvent&) { diagnostics_.force_update(); });
  // Also without extrapolation: the previous frame's estimate says whether its tf will come.
  if (options_.extrapolate_estimate || step_->builds_reference()) {
    estimates_ = std::make_unique<aar_ros_common::EstimateListener>(nh_, "aar/pose_estimate",
                                                                    options_.common.frames.tanker);
  }
  using Cloud = sensor_msgs::PointCloud2::ConstPtr;
  stage_ = std::make_unique<aar_ros_common::Stage<Cloud>>(
      options_.newest_wins, [this](Cloud& msg) { Cull(msg); },
      [](const Cloud& msg) { return msg->header.stamp; }, ledger_,
      aar_ros_common::Stage<Cloud>::Names{"occlusion", "cloud", "culling"});
  cloud_sub_ = nh_.subscribe("points", stage_->queue(5), &OcclusionNode::OnCloud, this);
  ROS_INFO_STREAM("occlusion: culling " << ToString(options_.step.cull) << ", "
                                        << (step_->boom() ? step_->boom()->parts().size() : 0)
                                        << " boom parts, " << step_->reference_samples()
                                        << " reference samples");
  aar_ros_common::AnnounceStart(private_nh, "occlusion");
}

OcclusionNode::~OcclusionNode() {
  diagnostics_timer_.stop();  // it reads members destroyed before it
  cloud_sub_.shutdown();
  stage_->Stop();
}

std::optional<Eigen::Isometry3d> OcclusionNode::Lookup(const std::string& frame,
                                                       const ros::Time& stamp, std::string* error) {
  return aar_ros_common::LookupTransformOrLatest(
      tf_buffer_, options_.common.frames.tanker, frame, stamp, options_.common.tf_timeout,
      options_.common.tf_fallback_age, "the cloud's stamp", error);
}

// The latest estimate as the predicted pose (moved on to `stamp` with extrapolate_estimate), once
// the previous cloud's estimate (usually on its way in lockstep) has come or estimate_wait has
// passed. Without extrapolation the pose is registration's tf, sent only for a valid estimate:
// after a miss there is no tf to wait for, and the latest older one is used at once.
std::optional<Eigen::Isometry3d> OcclusionNode::PredictedPose(const ros::Time& stamp) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(options_.estimate_wait);
  bool had_pose = true;  // unless its estimate came and said otherwise: its tf may still come
  bool valid = false;
  if (previous_stamp_ && options_.estimate_wait > 0.0 &&
      estimates_->WaitFor(*previous_stamp_, options_.estimate_wait, &valid))
    had_pose = valid;
  if (options_.extrapolate_estimate) {
    const auto p = estimates_->Predict(stamp, options_.common.estimate_max_age);
    if (!p) return std::nullopt;
    return p->T_tanker_receiver;
  }
  const double left = (deadline - ros::WallTime::now()).toSec();
  if (previous_stamp_ && had_pose && left > 0.0) {
    aar_ros_common::WaitForTransform(tf_buffer_, options_.common.frames.tanker,
                                     options_.common.frames.receiver, *previous_stamp_, left);
  }
  return aar_ros_common::LatestTransform(tf_buffer_, options_.common.frames.tanker,
                                         options_.common.frames.receiver, stamp,
                                         options_.common.estimate_max_age);
}

void OcclusionNode::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) { stage_->Hand(msg); }

void OcclusionNode::Cull(const sensor_msgs::PointCloud2::ConstPtr& msg) {
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
  reference_header.frame_id = options_.common.frames.receiver;
  OcclusionResult result;  // no reference: registration gets no target and skips the frame

  try {
    const aar_ros_common::CloudPoints cloud = aar_ros_common::FromCloud(*msg);
    const OcclusionInput in = GatherInput(*msg, cloud);
    result = step_->Process(in);
    if (result.out_of_range > 0) {
      ROS_WARN_STREAM_THROTTLE(
          5.0, "occlusion: " << result.out_of_range << " of " << in.points.size() << " points at "
                             << msg->header.stamp << " beyond max_point_range "
                             << options_.step.max_point_range << " m of the left camera: dropped");
    }
    error = result.cull_error;
    reference_error = result.reference_error;
    markers_stale_ |= result.volumes_rebuilt;
    std::vector<uint32_t> keep, removed;
    for (const size_t i : result.kept) keep.push_back(cloud.indices[i]);
    for (const size_t i : result.removed) removed.push_back(cloud.indices[i]);
    filtered = boost::make_shared<const sensor_msgs::PointCloud2>(
        aar_ros_common::SelectPoints(*msg, keep));
    boom_points = aar_ros_common::SelectPoints(*msg, removed);

    if (result.boom_placed && markers_stale_ && in.volumes_wanted) {
      std_msgs::Header h = msg->header;
      h.frame_id = options_.common.frames.tanker;
      markers_pub_.publish(ShadowMarkers(*step_->boom(), h, options_.marker_length));
      markers_stale_ = false;
    }
  } catch (const std::exception& e) {
    error = e.what();
    if (step_->builds_reference()) reference_error = "no reference without the cloud: " + error;
  }
  if (!error.empty()) ReportError("frame passes through unculled: " + error);
  if (!reference_error.empty()) ReportError("empty reference for this frame: " + reference_error);
  previous_stamp_ = msg->header.stamp;

  filtered_pub_.publish(filtered);
  ledger_.Passed(msg->header.stamp);  // culled, or passed through unculled (named above)
  // Shared pointers: nodelets in the same manager receive the message without a copy.
  const size_t boom_count = boom_points.width;
  boom_pub_.publish(boost::make_shared<sensor_msgs::PointCloud2>(std::move(boom_points)));
  if (step_->builds_reference()) {
    reference_pub_.publish(
        boost::make_shared<sensor_msgs::PointCloud2>(ToCloud(result.reference, reference_header)));
  }
  std::lock_guard<std::mutex> report(report_mutex_);
  ++frames_;
  unculled_frames_ += !error.empty();
  last_frame_error_ = error;
  last_reference_error_ = reference_error;
  reference_failures_ += !reference_error.empty();
  last_boom_points_ = boom_count;
  last_propeller_points_ = result.propeller_points;
  last_gated_points_ = result.gated;
  last_reference_both_ = result.reference.both;
  last_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

OcclusionInput OcclusionNode::GatherInput(const sensor_msgs::PointCloud2& msg,
                                          const aar_ros_common::CloudPoints& cloud) {
  std::string error;
  const ros::Time& stamp = msg.header.stamp;
  const auto T_tanker_cloud = Lookup(msg.header.frame_id, stamp, &error);
  const auto T_left = Lookup(options_.common.frames.left_camera, stamp, &error);
  const auto T_right = Lookup(options_.common.frames.right_camera, stamp, &error);
  if (!T_tanker_cloud || !T_left || !T_right) throw std::runtime_error(error);
  OcclusionInput in;
  in.points = cloud.points;
  for (auto& p : in.points) p = *T_tanker_cloud * p;
  in.left_eye = T_left->translation();
  in.right_eye = T_right->translation();
  in.volumes_wanted = markers_pub_.getNumSubscribers() > 0;
  if (step_->NeedsLinks(in.volumes_wanted)) {
    // One missing link leaves the boom unplaced: waiting tf_timeout for each of the others
    // too would put the stage behind the frames for as long as their tf is missing.
    for (const auto& link : step_->boom_links()) {
      auto T = Lookup(link, stamp, &in.links_error);
      if (!T) break;
      in.T_tanker_links[link] = *T;
    }
  }
  if (step_->builds_reference()) in.T_tanker_receiver_predicted = PredictedPose(stamp);
  return in;
}

void OcclusionNode::ReportError(const std::string& what) {
  if (errors_.ShouldLog(what)) ROS_ERROR_STREAM("occlusion: " << what);
}

void OcclusionNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(report_mutex_);
  status.add("frames", frames_);
  status.add("frames passed through unculled", unculled_frames_);
  status.add("frames without a reference", reference_failures_);
  for (const auto& [key, n] : ledger_.Counts()) status.add("ledger: " + key, n);
  status.add("cull method", ToString(options_.step.cull));
  status.add("boom points removed (last frame)", last_boom_points_);
  if (options_.step.cull_propellers)
    status.add("of them, on the propeller discs (last frame)", last_propeller_points_);
  if (options_.step.gate_receiver)
    status.add("points outside the receiver gate (last frame)", last_gated_points_);
  status.add("reference points seen by both cameras (last frame)", last_reference_both_);
  status.add("occlusion stage [ms] (last frame)", last_ms_);
  if (!step_->boom_error().empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "boom model refused, frames pass through unculled: " + step_->boom_error());
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
