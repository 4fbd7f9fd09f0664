#include "aar_sim/ros/sim_node.h"

#include <array>
#include <optional>
#include <stdexcept>

#include <aar_msgs/Visibility.h>
#include <aar_ros_common/markers.h>

#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <visualization_msgs/Marker.h>

#include <aar_description/boom_model.h>
#include "aar_sim/ros/conversions.h"

namespace aar_sim {

using aar_description::BoomJointPositions;
using aar_description::DefaultBoomPose;

SimNode::SimNode(ros::NodeHandle nh, const SimNodeOptions& options)
    : nh_(nh),
      options_(options),
      world_(std::make_unique<World>(options.world)),
      path_(FlightPath::Load(options.flight_path, {world_->boom_model().joints})),
      turbulence_(options.turbulence, path_.end_time()),
      it_(nh) {
  CheckStartTime();
  Advertise();
  PublishStatic();
  LogSettings();
  LogRealism();
}

void SimNode::CheckStartTime() const {
  if (options_.start_time < path_.start_time() || options_.start_time > path_.end_time()) {
    throw std::invalid_argument(
        "start_time " + std::to_string(options_.start_time) + " s is outside the flight path (" +
        std::to_string(path_.start_time()) + " to " + std::to_string(path_.end_time()) + " s)");
  }
  if (!(options_.stamp_offset + path_.start_time() > 0.0)) {
    throw std::invalid_argument(
        "stamp_offset + path start must be positive: stamps of 0 or less are not valid");
  }
}

void SimNode::Advertise() {
  // Raw cameras publish where a camera driver does (image_proc's rectify nodelets take them).
  const std::string image = options_.world.raw.enabled ? "image_raw" : "image_rect";
  rigs_.resize(1 + options_.more_rigs.size());
  for (size_t i = 0; i < rigs_.size(); ++i) {
    RigPublishers& r = rigs_[i];
    r.name = i == 0 ? "stereo" : options_.more_rigs[i - 1].name;
    r.rig = i == 0 ? &options_.world.rig : &options_.more_rigs[i - 1].rig;
    r.left_frame = r.name + "_left_optical";
    r.right_frame = r.name + "_right_optical";
    r.left = it_.advertiseCamera(r.name + "/left/" + image, 2);
    r.right = it_.advertiseCamera(r.name + "/right/" + image, 2);
    if (options_.publish_labels) {
      r.left_label = it_.advertise(r.name + "/left/label", 2);
      r.right_label = it_.advertise(r.name + "/right/label", 2);
    }
    if (options_.measure_visibility) {
      r.visibility = nh_.advertise<aar_msgs::Visibility>(
          i == 0 ? "sim/visibility" : "sim/" + r.name + "/visibility", 10);
    }
  }
  joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (options_.lockstep) {
    estimate_sub_ = nh_.subscribe("aar/pose_estimate", 10, &SimNode::OnEstimate, this);
  }
}

void SimNode::PublishStatic() {
  // The receiver model at truth, for rviz: latched, locked to the receiver_truth frame.
  marker_pub_ = nh_.advertise<visualization_msgs::Marker>("sim/receiver_model", 1, true);
  const aar_description::ReceiverDescription& receiver = options_.world.receiver;
  marker_pub_.publish(aar_ros_common::MeshMarker("receiver_truth", "receiver_truth", receiver.mesh,
                                                 aar_ros_common::Rgba(0.8f, 0.8f, 0.8f, 1.0f),
                                                 receiver.T_body_mesh, receiver.scale));
  const ros::Time now(options_.stamp_offset + path_.start_time());
  std::vector<geometry_msgs::TransformStamped> mounts = {
      ToTransformMsg(Eigen::Isometry3d::Identity(), now, "world", "tanker")};
  for (const RigPublishers& r : rigs_) {
    mounts.push_back(ToTransformMsg(r.rig->T_tanker_left_optical, now, "tanker", r.left_frame));
    mounts.push_back(ToTransformMsg(r.rig->T_tanker_right_optical(), now, "tanker", r.right_frame));
  }
  static_tf_.sendTransform(mounts);
}

void SimNode::LogSettings() const {
  ROS_INFO_STREAM(
      "sim: " << path_.rows().size() << " path rows over " << path_.end_time() - path_.start_time()
              << " s from " << options_.flight_path << "; renderer "
              << world_->renderer().gl_renderer() << "; "
              << (options_.lockstep ? "lockstep"
                                    : "free-running at " + std::to_string(options_.rate) + " Hz")
              << (!options_.lockstep && options_.realtime_factor != 1.0
                      ? " of path time, " + std::to_string(options_.realtime_factor) +
                            " path seconds per wall second"
                      : "")
              << (options_.world.boom_visible ? "" : "; boom hidden")
              << (rigs_.size() > 1 ? "; " + std::to_string(rigs_.size()) + " rigs" : "")
              << (world_->raw_left()
                      ? "; raw distorted images on " + rigs_[0].left.getTopic() + ", " +
                            rigs_[0].right.getTopic() + " (" +
                            std::to_string(100.0 * world_->raw_left()->outside_fraction()) +
                            " % of raw pixels beyond the rendered view)"
                      : ""));
}

void SimNode::LogRealism() const {
  const SunOptions& sun = options_.world.renderer.sun;
  if (sun.enabled) {
    ROS_INFO_STREAM("sim: the sun at azimuth "
                    << sun.azimuth_deg << " deg, elevation " << sun.elevation_deg << " deg"
                    << (sun.shadows ? ", cast shadows" : ", no shadows"));
  }
  if (options_.world.propellers != PropellerMode::kNone) {
    const size_t n = options_.world.receiver.propellers.size();
    if (n == 0) {  // a jet, or a description that does not list them: say so rather than nothing
      ROS_WARN_STREAM("sim: propellers are on, but the receiver description "
                      << options_.world.receiver.path << " lists none: none are drawn");
    } else {
      ROS_INFO_STREAM(
          "sim: " << n << " propellers drawn "
                  << (options_.world.propellers == PropellerMode::kDisc ? "as blurred discs"
                      : options_.world.sensor.motion_blur ? "as blades smeared over the exposure"
                                                          : "as blades frozen at the shutter"));
    }
  }
  if (turbulence_.enabled()) {
    const TurbulenceOptions& t = options_.turbulence;
    ROS_INFO_STREAM("sim: " << TurbulenceIntensityName(t.intensity) << " turbulence (Dryden, sigma "
                            << turbulence_.sigma() << " m/s at " << t.altitude << " m, "
                            << t.airspeed << " m/s; seed " << t.seed << ")");
  }
}

SimNode::~SimNode() {
  estimate_sub_.shutdown();  // no callback may touch the members below any more
  {
    std::lock_guard<std::mutex> lock(mutex_);  // under the lock: the wake-up cannot be lost
    stop_ = true;
  }
  estimate_arrived_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SimNode::Run() {
  try {
    Loop();
  } catch (const std::exception& e) {  // never let an exception end the process from this thread
    ROS_FATAL_STREAM("sim: frame loop stopped: " << e.what());
    failed_ = true;
  }
  finished_ = true;
  if (options_.shutdown_at_end) ros::requestShutdown();
}

void SimNode::Start() { thread_ = std::thread(&SimNode::Run, this); }

void SimNode::OnEstimate(const ros::MessageEvent<aar_msgs::PoseEstimate const>& event) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!intrusion_.empty()) return;
    intrusion_ = Intrusion(event.getPublisherName());
    const ros::Time& stamp = event.getConstMessage()->header.stamp;
    if (intrusion_.empty() && stamp > last_estimate_stamp_) last_estimate_stamp_ = stamp;
  }
  estimate_arrived_.notify_all();
}

std::string SimNode::Intrusion(const std::string& caller) {
  if (!check_) {
    const std::string node =
        options_.estimate_publisher.empty() ? caller : options_.estimate_publisher;
    if (options_.estimate_publisher.empty()) {
      ROS_INFO_STREAM("sim: lockstep on the estimates of " << node
                                                           << " (the first publisher "
                                                              "heard; set ~estimate_publisher "
                                                              "to name it)");
    }
    check_.emplace(estimate_sub_.getTopic(), node);
  }
  std::vector<std::string> named = check_->StrangersIfChanged(estimate_sub_.getNumPublishers());
  if (caller != check_->node()) named.push_back("caller " + caller);
  if (named.empty()) return "";
  return "another node publishes on " + estimate_sub_.getTopic() + " at " +
         check_->Describe(named) +
         ": its estimates cannot be told from the registration's; stopping the lockstep run";
}

void SimNode::WaitToStart() const {
  if (options_.wait_for_subscribers) {
    // Every rig's: a rig whose stereo subscribed late would miss the first frames.
    ROS_INFO_STREAM("sim: waiting for subscribers to both images of "
                    << rigs_.size() << (rigs_.size() > 1 ? " rigs" : " rig"));
    auto unheard = [this] {
      for (const auto& rig : rigs_)
        if (rig.left.getNumSubscribers() == 0 || rig.right.getNumSubscribers() == 0) return true;
      return false;
    };
    while (!stop_ && ros::ok() && unheard()) ros::WallDuration(0.05).sleep();
  }
  // In steps, so that a shutdown (the launch ending) is not held up by the delay.
  const ros::WallTime start = ros::WallTime::now() + ros::WallDuration(options_.start_delay);
  while (!stop_ && ros::ok() && ros::WallTime::now() < start) ros::WallDuration(0.05).sleep();
}

int SimNode::FrameCount() const {
  const int path_frames = static_cast<int>(std::floor(
                              (path_.end_time() - options_.start_time) * options_.rate + 1e-9)) +
                          1;
  return options_.max_frames > 0 ? std::min(options_.max_frames, path_frames) : path_frames;
}

StereoFrame SimNode::RenderFrame(int k, double t, const FlightPathRow& row, const BoomPose& boom,
                                 size_t rig) {
  // Motion blur integrates from t to the exposure's end; the truth is the state at t.
  std::optional<SceneState> exposure_end;
  if (options_.world.sensor.motion_blur) {
    const auto [row_end, boom_end] = StateAt(t + options_.world.sensor.exposure_time);
    exposure_end = SceneState{row_end, boom_end};
  }
  try {
    return world_->RenderRig(*rigs_[rig].rig, rig, row, boom, static_cast<uint64_t>(k),
                             options_.publish_labels || options_.measure_visibility, false,
                             exposure_end ? &*exposure_end : nullptr);
  } catch (const std::exception& e) {
    throw std::runtime_error("rendering frame " + std::to_string(k) + " failed: " + e.what());
  }
}

bool SimNode::WaitForEstimate(int k, const ros::Time& stamp) {
  std::unique_lock<std::mutex> lock(mutex_);
  const bool arrived = estimate_arrived_.wait_for(
      lock, std::chrono::duration<double>(options_.lockstep_timeout),
      [&] { return stop_ || last_estimate_stamp_ >= stamp || !intrusion_.empty(); });
  if (!intrusion_.empty()) throw std::runtime_error(intrusion_);
  if (!arrived) {
    ROS_WARN_STREAM("sim: no pose estimate for frame " << k << " (stamp " << stamp << ") within "
                                                       << options_.lockstep_timeout
                                                       << " s; going on");
  }
  return arrived;
}

void SimNode::Loop() {
  WaitToStart();
  const int frames = FrameCount();
  const auto period =
      std::chrono::duration<double>(1.0 / (options_.rate * options_.realtime_factor));
  auto next = std::chrono::steady_clock::now();
  int misses = 0;
  for (int k = 0; k < frames && !stop_ && ros::ok(); ++k) {
    const double t = options_.start_time + k / options_.rate;
    const auto [row, boom] = StateAt(t);
    const ros::Time stamp(options_.stamp_offset + t);
    PublishFrame(k, row, boom, RenderFrame(k, t, row, boom), stamp);
    PublishMoreRigs(k, t, row, boom, stamp);
    if (options_.lockstep) {
      if (!WaitForEstimate(k, stamp)) ++misses;
    } else {  // a wall-clock rate, interruptible by the destructor
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      std::unique_lock<std::mutex> lock(mutex_);
      estimate_arrived_.wait_until(lock, next, [&] { return bool(stop_); });
    }
    ROS_DEBUG_STREAM("sim: frame " << k + 1 << "/" << frames << ", range " << row.position_m.norm()
                                   << " m");
  }
  ROS_INFO_STREAM("sim: flight path done, "
                  << frames << " frames"
                  << (options_.lockstep ? ", " + std::to_string(misses) + " without an estimate"
                                        : ""));
}

std::pair<FlightPathRow, BoomPose> SimNode::StateAt(double t) const {
  const FlightPathRow row = path_.At(t);
  const BoomPose boom = row.boom.value_or(DefaultBoomPose());
  return turbulence_.Apply(t, row, boom, world_->boom_model().joints);
}

void SimNode::PublishVisibility(const ros::Publisher& pub,
                                const std::array<ViewVisibility, 2>& views,
                                const ros::Time& stamp) {
  aar_msgs::Visibility msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = "tanker";
  for (int camera = 0; camera < 2; ++camera) {
    msg.camera.push_back(camera == 0 ? "left" : "right");
    msg.silhouette_px.push_back(static_cast<uint32_t>(views[camera].silhouette_px));
    msg.visible_px.push_back(static_cast<uint32_t>(views[camera].visible_px));
  }
  pub.publish(msg);
}

void SimNode::PublishFrame(int index, const FlightPathRow& row, const BoomPose& boom,
                           const StereoFrame& frame, const ros::Time& stamp) {
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  clock_pub_.publish(clock);

  sensor_msgs::JointState joints;
  joints.header.stamp = stamp;
  for (const auto& [name, value] : BoomJointPositions(boom)) {
    joints.name.push_back(name);
    joints.position.push_back(value);
  }
  joint_pub_.publish(joints);
  tf_.sendTransform(ToTransformMsg(row.T_tanker_receiver(), stamp, "tanker", "receiver_truth"));
  PublishImages(0, index, frame, stamp);
}

void SimNode::PublishMoreRigs(int k, double t, const FlightPathRow& row, const BoomPose& boom,
                              const ros::Time& stamp) {
  for (size_t i = 1; i < rigs_.size(); ++i)
    PublishImages(i, k, RenderFrame(k, t, row, boom, i), stamp);
}

void SimNode::PublishImages(size_t rig, int index, const StereoFrame& frame,
                            const ros::Time& stamp) {
  const RigPublishers& r = rigs_[rig];
  if (options_.measure_visibility) {
    PublishVisibility(r.visibility, world_->MeasureVisibility(frame, *r.rig), stamp);
  }
  const CameraIntrinsics& k = r.rig->intrinsics;
  std_msgs::Header left, right;
  left.stamp = right.stamp = stamp;
  left.seq = right.seq = static_cast<uint32_t>(index);
  // Both in the left optical frame, ROS's stereo convention: the right camera's P (with
  // Tx = -f * baseline) projects points given in the left camera's frame, and image_geometry
  // (hence stereo_image_proc) asserts the frames are equal. The right camera's own pose is the
  // tf frame NAME_right_optical.
  left.frame_id = right.frame_id = r.left_frame;
  const double Tx = -k.fx * r.rig->baseline;
  if (const RawCamera* raw_left = world_->raw_left()) {
    r.left.publish(ToImageMsg(frame.left_raw, left), ToRawCameraInfoMsg(*raw_left, k, 0.0, left));
    r.right.publish(ToImageMsg(frame.right_raw, right),
                    ToRawCameraInfoMsg(*world_->raw_right(), k, Tx, right));
  } else {
    r.left.publish(ToImageMsg(frame.left.image, left), ToCameraInfoMsg(k, 0.0, left));
    r.right.publish(ToImageMsg(frame.right.image, right), ToCameraInfoMsg(k, Tx, right));
  }
  if (options_.publish_labels) {
    r.left_label.publish(ToImageMsg(frame.left.label, left));
    r.right_label.publish(ToImageMsg(frame.right.label, right));
  }
}

}  // namespace aar_sim
