#include "aar_registration/ros/registration_node.h"

#include <chrono>
#include <set>
#include <sstream>

#include <boost/bind/bind.hpp>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_msgs/PoseEstimate.h>
#include <aar_ros_common/markers.h>
#include <aar_ros_common/point_cloud.h>
#include <aar_ros_common/receiver_params.h>
#include <aar_ros_common/start_count.h>
#include <aar_ros_common/tf_bridge.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "aar_registration/ros/conversions.h"

namespace aar_registration {

RegistrationNode::RegistrationNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                                   const RegistrationNodeOptions& options)
    : nh_(nh),
      options_(options),
      tf_listener_(tf_buffer_),
      registrar_(options.registrar),
      diagnostics_(nh, private_nh),
      ledger_(nh, "registration") {
  diagnostics_.setHardwareID("registration");
  diagnostics_.add("registration", this, &RegistrationNode::Diagnose);
  diagnostics_timer_ =
      nh_.createWallTimer(ros::WallDuration(options_.common.diagnostic_period),
                          [this](const ros::WallTimerEvent&) { diagnostics_.force_update(); });
  pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("aar/receiver_pose", 10);
  estimate_pub_ = nh_.advertise<aar_msgs::PoseEstimate>("aar/pose_estimate", 10);
  // The mesh, for the static reference and the outline, loaded once; a mesh that does not load
  // ends the node: a configuration error.
  if (options_.registrar.outline.enabled || options_.registrar.reference != ReferenceKind::kTopic)
    receiver_mesh_ = aar_description::LoadReceiverMesh(options_.receiver);
  if (options_.registrar.outline.enabled) {
    registrar_.SetOutlineModel(receiver_mesh_);
    outline_ = std::make_unique<OutlineInputs>(
        nh_, tf_buffer_, options_.common.frames.tanker,
        options_.model_boom ? options_.common.robot_description : "", options_.common.tf_timeout,
        options_.common.tf_fallback_age);
    outline_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("aar/outline_pose", 10);
    for (size_t i = 1; i < options_.rigs.size(); ++i)  // the first rig's frame has the boom
      more_outlines_.push_back(std::make_unique<OutlineInputs>(
          nh_, tf_buffer_, options_.common.frames.tanker, "", options_.common.tf_timeout,
          options_.common.tf_fallback_age, options_.rigs[i] + "/"));
  }
  PublishModels();
  // newest_wins: the callbacks only hand over to the registering thread, where an input still
  // waiting when a newer one comes is superseded (the ledger counts it).
  stage_ = std::make_unique<aar_ros_common::Stage<Input>>(
      options_.newest_wins, [this](Input& input) { Process(input); },
      [](const Input& input) { return input.stamp; }, ledger_,
      aar_ros_common::Stage<Input>::Names{"registration", "cloud", "registration"});
  const uint32_t queue = stage_->queue(5);
  if (options_.registrar.reference == ReferenceKind::kTopic) {
    // Each cloud is registered to the reference built for its own frame (same stamp).
    points_filter_.subscribe(nh_, "points", queue);
    reference_filter_.subscribe(nh_, "aar/reference_cloud", queue);
    sync_ = std::make_unique<Sync>(points_filter_, reference_filter_, 10);
    sync_->registerCallback(&RegistrationNode::OnPair, this);
    // A cloud whose reference never comes still gets an answer (an invalid estimate), so that
    // lockstep moves on and the log says what is missing.
    cloud_sub_ = nh_.subscribe("points", queue, &RegistrationNode::OnPointsSeen, this);
    if (options_.rigs.size() > 1) SubscribeRigs(queue);
    pending_timer_ =
        nh_.createWallTimer(ros::WallDuration(0.1), &RegistrationNode::ExpirePending, this);
  } else {
    // The cameras' tf may come later (start-up order): frames until then get no estimate.
    reference_wait_since_ = ros::WallTime::now();
    if (!TryBuildStaticReference(2.0)) {
      reference_timer_ =
          nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
            try {
              if (TryBuildStaticReference(0.0)) reference_timer_.stop();
            } catch (const std::exception& e) {  // stays up: the frames say why, no estimate
              ROS_ERROR_STREAM("registration: no reference model: " << e.what());
              reference_timer_.stop();
            }
          });
    }
    cloud_sub_ = nh_.subscribe("points", stage_->queue(2), &RegistrationNode::OnCloud, this);
  }
  aar_ros_common::AnnounceStart(private_nh, "registration");
}

RegistrationNode::~RegistrationNode() {
  diagnostics_timer_.stop();  // it reads members destroyed before it
  pending_timer_.stop();
  reference_timer_.stop();
  cloud_sub_.shutdown();
  points_filter_.unsubscribe();
  reference_filter_.unsubscribe();
  for (auto& rig : rig_inputs_) {
    rig->points.unsubscribe();
    rig->reference.unsubscribe();
  }
  stage_->Stop();
}

void RegistrationNode::SubscribeRigs(uint32_t queue) {
  gather_ = std::make_unique<RigGather>(options_.rigs.size());
  rig_missing_.assign(options_.rigs.size(), 0);
  for (size_t i = 1; i < options_.rigs.size(); ++i) {
    auto rig = std::make_unique<RigInputs>();
    rig->points.subscribe(nh_, options_.rigs[i] + "/aar/points_filtered", queue);
    rig->reference.subscribe(nh_, options_.rigs[i] + "/aar/reference_cloud", queue);
    rig->sync = std::make_unique<Sync>(rig->points, rig->reference, 10);
    rig->sync->registerCallback(boost::bind(&RegistrationNode::OnRigPair, this, i,
                                            boost::placeholders::_1, boost::placeholders::_2));
    rig_inputs_.push_back(std::move(rig));
  }
  ROS_INFO_STREAM("registration: " << options_.rigs.size() << " rigs, a frame waits up to "
                                   << options_.rig_wait << " s for each rig's cloud");
}

bool RegistrationNode::TryBuildStaticReference(double tf_wait) {
  const auto start = std::chrono::steady_clock::now();
  // The camera positions, for shelling as they see the receiver at the nominal pose.
  std::vector<Eigen::Vector3d> eyes;
  if (options_.registrar.reference != ReferenceKind::kDense) {
    for (const auto& frame :
         {options_.common.frames.left_camera, options_.common.frames.right_camera}) {
      std::string error;
      const auto T_tanker_camera =
          aar_ros_common::LookupTransform(tf_buffer_, options_.common.frames.tanker, frame,
                                          ros::Time(0), tf_wait, "any time", &error);
      if (!T_tanker_camera) {
        const double waited = (ros::WallTime::now() - reference_wait_since_).toSec();
        if (waited >= 5.0) {
          ROS_WARN_STREAM_THROTTLE(10.0, "registration: waited "
                                             << static_cast<int>(waited) << " s: " << error
                                             << ", needed to shell the reference model; frames "
                                                "until then have no estimate");
        }
        return false;
      }
      eyes.push_back(T_tanker_camera->translation());
    }
  }
  size_t size = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    size = registrar_.BuildStaticReference(receiver_mesh_, eyes);
  }
  receiver_mesh_ = aar_geometry::TriangleMesh();  // not needed again
  ROS_INFO_STREAM("registration: reference model of "
                  << size << " points built in "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
                  << " s");
  return true;
}

std::string RegistrationNode::StampProblem(const ros::Time& stamp) const {
  if (stamp.isZero()) return "the cloud's stamp is 0";
  const ros::Time now = ros::Time::now();
  // Under sim time the clock is 0 until the first /clock: nothing to compare with yet.
  if (!now.isZero() && (stamp - now).toSec() > options_.max_stamp_lead) {
    std::ostringstream s;
    s << "the cloud's stamp " << stamp << " is " << (stamp - now).toSec()
      << " s ahead of the clock (" << now << "; max_stamp_lead " << options_.max_stamp_lead
      << " s)";
    return s.str();
  }
  return "";
}

void RegistrationNode::OnPointsSeen(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(pending_mutex_);
  if (!answered_.count(msg->header.stamp)) pending_[msg->header.stamp] = ros::WallTime::now();
}

void RegistrationNode::ExpirePending(const ros::WallTimerEvent&) {
  std::vector<ros::Time> expired;
  std::vector<RigGather::Frame> gathered;  // more than one rig: frames that waited rig_wait
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    const ros::WallTime now = ros::WallTime::now();
    if (gather_) gathered = gather_->Expire(now, options_.rig_wait);
    for (const auto& frame : gathered) {
      answered_.insert(frame.first);
      pending_.erase(frame.first);
    }
    for (auto it = pending_.begin(); it != pending_.end();) {
      // A frame another rig's cloud came for is the gather's to answer.
      if (gather_ && gather_->Holds(it->first)) {
        ++it;
      } else if ((now - it->second).toSec() > options_.reference_timeout) {
        expired.push_back(it->first);
        answered_.insert(it->first);
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
    while (answered_.size() > 100) answered_.erase(answered_.begin());
  }
  for (auto& frame : gathered) stage_->Hand(Input{frame.first, std::move(frame.second)});
  for (const ros::Time& stamp : expired) {
    RegistrarResult none;
    none.error = "no reference cloud with the points' stamp within " +
                 std::to_string(options_.reference_timeout) + " s";
    ReportError(none.error +
                ": is occlusion_node publishing aar/reference_cloud (publish_reference), or did "
                "it skip this cloud for a newer one (newest_wins)?");
    Publish(none, stamp, 0.0);
  }
}

void RegistrationNode::OnPair(const sensor_msgs::PointCloud2::ConstPtr& points,
                              const sensor_msgs::PointCloud2::ConstPtr& reference) {
  if (gather_) return OnRigPair(0, points, reference);
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    if (answered_.count(points->header.stamp)) return;  // already answered as expired
    answered_.insert(points->header.stamp);
    pending_.erase(points->header.stamp);
  }
  stage_->Hand(Input{points->header.stamp, {{points, reference}}});
}

void RegistrationNode::OnRigPair(size_t rig, const sensor_msgs::PointCloud2::ConstPtr& points,
                                 const sensor_msgs::PointCloud2::ConstPtr& reference) {
  std::vector<RigGather::Frame> ready;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    // A rig's cloud after its frame was registered without it: counted there as missing.
    if (answered_.count(points->header.stamp)) return;
    ready = gather_->Add(rig, points->header.stamp, {points, reference}, ros::WallTime::now());
    for (const auto& frame : ready) {
      answered_.insert(frame.first);
      pending_.erase(frame.first);
    }
  }
  for (auto& frame : ready) stage_->Hand(Input{frame.first, std::move(frame.second)});
}

void RegistrationNode::Process(const Input& input) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (options_.registrar.reference == ReferenceKind::kTopic) {
    try {
      std::vector<ReferencePoints> rigs;
      for (const RigGather::Cloud& cloud : input.clouds)
        if (cloud.reference) rigs.push_back(ToReferencePoints(*cloud.reference));
      // One rig: its reference as it came; more: the union (each rig's own view of the mesh).
      ReferencePoints ref =
          rigs.size() == 1 ? std::move(rigs.front()) : MergeReferences(std::move(rigs));
      registrar_.SetReference(std::move(ref.points), std::move(ref.normals));
    } catch (const std::exception& e) {  // no stale target: this frame gets no estimate
      ReportError(std::string("reference cloud rejected: ") + e.what());
    }
  }
  if (gather_) CountMissingRigs(input);
  Register(input);
}

void RegistrationNode::CountMissingRigs(const Input& input) {
  std::ostringstream missing;
  {
    std::lock_guard<std::mutex> report(report_mutex_);
    for (size_t i = 0; i < input.clouds.size(); ++i) {
      if (input.clouds[i].points) continue;
      missing << (missing.tellp() > 0 ? ", " : "") << options_.rigs[i] << " (" << ++rig_missing_[i]
              << " such frames so far)";
    }
  }
  if (missing.tellp() == 0) return;
  ROS_WARN_STREAM_THROTTLE(5.0, "registration: frame "
                                    << input.stamp << " registered without the clouds of "
                                    << missing.str() << ", which did not come within "
                                    << options_.rig_wait
                                    << " s (rig_wait): is each rig's "
                                       "stereo and occlusion running?");
}

void RegistrationNode::ReportError(const std::string& what) {
  if (errors_.ShouldLog(what)) ROS_ERROR_STREAM("registration: " << what);
}

void RegistrationNode::OnCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  stage_->Hand(Input{msg->header.stamp, {{msg, nullptr}}});
}

void RegistrationNode::Register(const Input& input) {
  const auto received = std::chrono::steady_clock::now();
  auto total_ms = [&] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - received)
        .count();
  };
  const ros::Time& stamp = input.stamp;
  const std::string problem = StampProblem(stamp);
  // A cloud older than the last one registered came late: the tracker must not go back in time
  // (it would start a new track), and its estimate would be stale. Dropped, without an estimate.
  if (const std::string late =
          problem.empty() ? order_.Check(stamp, ros::Time::now()) : std::string();
      !late.empty()) {
    const std::string what =
        "registration: cloud on " + nh_.resolveName("points") + " dropped, no estimate: " + late;
    ledger_.Dropped(stamp, "out_of_order", late);
    if (errors_.ShouldLog(what))
      ROS_WARN_STREAM(what << " (" << order_.dropped() << " dropped so far)");
    return;
  }
  RegistrarResult result;
  try {
    if (!problem.empty()) throw std::runtime_error(problem);
    // The registrar says so too, but only after the tf wait this saves. With the outline the
    // frame goes on: where the boom hides the receiver from one camera the reference (what both
    // see) can be empty while the outline still fits in the other (issue 44).
    if (!registrar_.has_reference() && !outline_)
      throw std::runtime_error("no reference model yet");
    const std::vector<Eigen::Vector3d> sensed = SensedInTanker(input);
    std::optional<Eigen::Vector3d> eye;  // stereo-ray ICP pairs along the left camera's rays
    if (options_.registrar.icp.metric == IcpMetric::kStereoRays) {
      std::string error;
      const auto T_tanker_left = aar_ros_common::LookupTransform(
          tf_buffer_, options_.common.frames.tanker, options_.common.frames.left_camera, stamp,
          options_.common.tf_timeout, "the cloud's stamp", &error);
      if (!T_tanker_left) throw std::runtime_error("stereo_rays ICP: " + error);
      eye = T_tanker_left->translation();
    }
    const std::optional<OutlineFrame> outline = OutlineOf(stamp);
    result = registrar_.Register(sensed, stamp.toSec(), outline ? &*outline : nullptr,
                                 eye ? &*eye : nullptr);
    if (result.outline_ran) PublishOutline(result, stamp);
    if (result.cut_from_points > 0) {
      ROS_WARN_STREAM_THROTTLE(5.0, "registration: a cloud of "
                                        << result.cut_from_points << " points at " << stamp
                                        << ": registered a random " << result.sensed_points
                                        << " of them (max_cloud_points)");
    }
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  if (!result.valid)
    ReportError("cloud not registered, no estimate for this frame: " + result.error);
  if (result.tracking) {
    const TrackOutcome outcome = result.track.outcome;
    if ((outcome == TrackOutcome::kLost || outcome == TrackOutcome::kReset) &&
        errors_.ShouldLog("track " + std::string(ToString(outcome))))
      ROS_WARN_STREAM("registration: track " << ToString(outcome) << " at " << stamp
                                             << ", acquiring again: " << result.track.reason);
  }
  Publish(result, stamp, total_ms());
  if (result.valid) {
    ROS_DEBUG_STREAM("registration: " << stamp << ": " << result.icp.iterations
                                      << " iterations, rms " << result.icp.rms << " m, "
                                      << result.registration_ms << " ms"
                                      << (result.icp.converged ? "" : " (not converged)"));
  }
}

std::vector<Eigen::Vector3d> RegistrationNode::SensedInTanker(const Input& input) {
  std::vector<Eigen::Vector3d> sensed;
  for (const RigGather::Cloud& cloud : input.clouds) {
    if (!cloud.points) continue;  // this rig's did not come
    const sensor_msgs::PointCloud2& msg = *cloud.points;
    std::string error;
    const auto T_tanker_cloud = aar_ros_common::LookupTransform(
        tf_buffer_, options_.common.frames.tanker, msg.header.frame_id, msg.header.stamp,
        options_.common.tf_timeout, "the cloud's stamp", &error);
    if (!T_tanker_cloud) throw std::runtime_error(error);
    for (const Eigen::Vector3d& p : aar_ros_common::FromCloud(msg).points)
      sensed.push_back(*T_tanker_cloud * p);
  }
  return sensed;
}

std::optional<OutlineFrame> RegistrationNode::OutlineOf(const ros::Time& stamp) {
  if (!outline_) return std::nullopt;
  std::string missing;
  std::optional<OutlineFrame> frame = outline_->Get(stamp, &missing);
  // Further rigs' images join the first rig's frame (its boom parts are every rig's).
  for (size_t i = 0; frame && i < more_outlines_.size(); ++i) {
    std::string rig_missing;
    if (std::optional<OutlineFrame> rig = more_outlines_[i]->Get(stamp, &rig_missing))
      frame->more_rigs.push_back({rig->left, rig->right, rig->left_camera, rig->right_camera});
    else
      missing = options_.rigs[i + 1] + ": " + rig_missing;
  }
  if (!missing.empty()) {
    std::lock_guard<std::mutex> lock(report_mutex_);
    ++outline_missing_;
    last_outline_missing_ = missing;
  }
  return frame;
}

void RegistrationNode::PublishOutline(const RegistrarResult& result, const ros::Time& stamp) {
  {
    std::lock_guard<std::mutex> lock(report_mutex_);
    ++outline_ran_;
    outline_fused_ += result.outline_fused;
    last_outline_quality_ = result.outline.quality;
    if (!result.outline_note.empty()) last_outline_note_ = result.outline_note;
  }
  if (!result.outline.valid) return;
  geometry_msgs::PoseWithCovarianceStamped pose;
  pose.header.stamp = stamp;
  pose.header.frame_id = options_.common.frames.tanker;
  pose.pose.pose = tf2::toMsg(result.outline.T_tanker_receiver);
  for (int i = 0; i < 36; ++i) pose.pose.covariance[i] = result.outline.covariance(i / 6, i % 6);
  outline_pub_.publish(pose);
}

void RegistrationNode::Publish(const RegistrarResult& result, const ros::Time& stamp,
                               double total_ms) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = options_.common.frames.tanker;
  const aar_msgs::PoseEstimate estimate = ToPoseEstimate(result, header, total_ms);
  {
    std::lock_guard<std::mutex> lock(report_mutex_);
    ++frames_;
    last_error_ = result.valid ? "" : result.error;
    if (result.valid && result.integrity.alert) {
      ++integrity_alerts_;
      last_integrity_reason_ = result.integrity.reason;
    }
    if (result.tracking) {
      ++outcomes_[result.track.outcome];
      last_outcome_ = result.track.outcome;
      if (!result.track.reason.empty()) last_track_reason_ = result.track.reason;
    }
  }
  if (result.valid) {
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header = header;
    pose.pose.pose = estimate.pose;
    pose.pose.covariance = estimate.covariance;
    geometry_msgs::TransformStamped tf = tf2::eigenToTransform(result.T_tanker_receiver);
    tf.header = header;
    tf.child_frame_id = options_.common.frames.receiver;
    tf_broadcaster_.sendTransform(tf);
    pose_pub_.publish(pose);
  }
  estimate_pub_.publish(estimate);
  if (result.valid)
    ledger_.Passed(stamp);
  else  // the estimate says "no pose"; the ledger says why
    ledger_.Dropped(stamp, "no_pose", result.error.empty() ? "no registration" : result.error);
}

void RegistrationNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(report_mutex_);
  status.add("frames", frames_);
  // Estimated ("frames passed") and dropped by reason (out_of_order, superseded, no_pose): the
  // ledger's.
  for (const auto& [key, n] : ledger_.Counts()) status.add("ledger: " + key, n);
  status.add("tracking", options_.registrar.track);
  for (const auto& [outcome, count] : outcomes_)
    status.add(std::string("frames ") + ToString(outcome), count);
  if (!last_track_reason_.empty()) status.add("last track event", last_track_reason_);
  status.add("poses in integrity alert", integrity_alerts_);
  if (!last_integrity_reason_.empty()) status.add("last integrity alert", last_integrity_reason_);
  if (outline_) {
    status.add("outline: frames aligned", outline_ran_);
    status.add("outline: frames fused", outline_fused_);
    status.add("outline: frames without its inputs", outline_missing_);
    status.add("outline: image pairs received", outline_->pairs_received());
    status.add("outline: last fit", last_outline_quality_);
    if (!last_outline_note_.empty()) status.add("outline: last event", last_outline_note_);
    if (!last_outline_missing_.empty())
      status.add("outline: last missing input", last_outline_missing_);
    if (!outline_->boom_error().empty())
      status.add("outline: boom not masked", outline_->boom_error());
  }
  for (size_t i = 0; i < rig_missing_.size(); ++i)
    status.add("rigs: frames registered without " + options_.rigs[i], rig_missing_[i]);
  if (!last_error_.empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "last frame has no estimate: " + last_error_);
  } else if (options_.registrar.track && frames_ > 0 &&
             (last_outcome_ == TrackOutcome::kRejected || last_outcome_ == TrackOutcome::kMissed)) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "coasting on the prediction: " + last_track_reason_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, frames_ > 0 ? "estimating" : "no input");
  }
}

void RegistrationNode::PublishModels() {
  // The receiver model at the estimate (orange) and at truth (grey), for rviz: latched, each
  // locked to its frame, shown where tf has that frame (truth: simulations and their bags).
  models_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("aar/receiver_models", 1, true);
  visualization_msgs::MarkerArray models;
  models.markers.push_back(aar_ros_common::MeshMarker(
      options_.common.frames.receiver, "estimate", options_.receiver.mesh,
      aar_ros_common::Rgba(1.0f, 0.55f, 0.1f, 0.6f), options_.receiver.T_body_mesh,
      options_.receiver.scale));
  models.markers.push_back(
      aar_ros_common::MeshMarker(options_.truth_frame, "truth", options_.receiver.mesh,
                                 aar_ros_common::Rgba(0.8f, 0.8f, 0.8f, 1.0f),
                                 options_.receiver.T_body_mesh, options_.receiver.scale));
  models_pub_.publish(models);
}

}  // namespace aar_registration
