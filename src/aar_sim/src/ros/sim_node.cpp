#include "aar_sim/ros/sim_node.h"

#include <set>

#include <ros/package.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <visualization_msgs/Marker.h>

#include <filesystem>

#include "aar_sim/boom_model.h"
#include "aar_sim/ros/conversions.h"

namespace aar_sim {
namespace {

template <typename T>
T Param(const ros::NodeHandle& nh, const std::string& name, const T& fallback,
        std::set<std::string>& known) {
  known.insert(nh.resolveName(name));
  T value = fallback;
  if (nh.hasParam(name) && !nh.getParam(name, value)) {
    throw std::invalid_argument("parameter " + nh.resolveName(name) + " has the wrong type");
  }
  return value;
}

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

SimNodeOptions LoadSimNodeOptions(const ros::NodeHandle& nh) {
  SimNodeOptions o;
  std::set<std::string> known;
  known.insert(nh.resolveName("robot_description"));  // tolerated: some launch files put it here
  if (!nh.getParam("flight_path", o.flight_path) || o.flight_path.empty()) {
    throw std::invalid_argument("required parameter " + nh.resolveName("flight_path") +
                                " (a flight-path CSV) is not set");
  }
  known.insert(nh.resolveName("flight_path"));
  const std::string models = ros::package::getPath("aar_sim") + "/models";
  o.world.receiver_mesh = Param<std::string>(nh, "receiver_mesh", models + "/receiver.obj", known);
  o.world.boom_urdf = Param<std::string>(nh, "boom_urdf", models + "/boom.urdf", known);
  o.world.boom_visible = Param(nh, "boom", true, known);

  const int width = Param(nh, "image_width", 1280, known);
  const int height = Param(nh, "image_height", 960, known);
  const double hfov = Param(nh, "hfov_deg", 60.0, known);
  const double baseline = Param(nh, "baseline", 0.5, known);
  const Eigen::Vector3d mount(Param(nh, "camera_x", -20.0, known),
                              Param(nh, "camera_y", 1.0, known),
                              Param(nh, "camera_z", -3.0, known));
  const double yaw = Param(nh, "camera_yaw_deg", 180.0, known);
  const double pitch = Param(nh, "camera_pitch_deg", 25.0, known);
  Require(width > 0 && height > 0, "image_width and image_height must be positive");
  Require(hfov > 0.0 && hfov < 180.0, "hfov_deg must be in (0, 180)");
  Require(baseline > 0.0, "baseline must be positive");
  o.world.rig = MakeStereoRig(CameraIntrinsics::FromHorizontalFov(width, height, hfov), baseline,
                              mount, yaw, pitch);

  o.world.renderer.noise_stddev = Param(nh, "noise_stddev", 0.0, known);
  o.world.renderer.noise_seed = static_cast<uint64_t>(Param(nh, "noise_seed", 1, known));
  o.world.renderer.sky_level = Param(nh, "sky_level", 200.0, known);
  Require(o.world.renderer.noise_stddev >= 0.0, "noise_stddev must not be negative");

  o.rate = Param(nh, "rate", o.rate, known);
  o.start_time = Param(nh, "start_time", o.start_time, known);
  o.max_frames = Param(nh, "frames", o.max_frames, known);
  o.lockstep = Param(nh, "lockstep", o.lockstep, known);
  o.lockstep_timeout = Param(nh, "lockstep_timeout", o.lockstep_timeout, known);
  o.wait_for_subscribers = Param(nh, "wait_for_subscribers", o.lockstep, known);
  o.start_delay = Param(nh, "start_delay", o.start_delay, known);
  Require(o.start_delay >= 0.0, "start_delay must not be negative");
  o.publish_labels = Param(nh, "publish_labels", o.publish_labels, known);
  o.shutdown_at_end = Param(nh, "shutdown_at_end", o.shutdown_at_end, known);
  o.stamp_offset = Param(nh, "stamp_offset", o.stamp_offset, known);
  Require(o.rate > 0.0, "rate must be positive");
  Require(o.max_frames >= 0, "frames must not be negative");
  Require(o.lockstep_timeout > 0.0, "lockstep_timeout must be positive");
  Require(o.stamp_offset > 0.0, "stamp_offset must be positive");

  std::vector<std::string> names;
  nh.getParamNames(names);
  const std::string prefix = nh.getNamespace() + "/";
  for (const auto& name : names) {
    if (name.rfind(prefix, 0) == 0 && !known.count(name)) {
      throw std::invalid_argument("unknown parameter " + name + " (misspelt?)");
    }
  }
  return o;
}

SimNode::SimNode(ros::NodeHandle nh, const SimNodeOptions& options)
    : nh_(nh),
      options_(options),
      path_(FlightPath::Load(options.flight_path)),
      world_(std::make_unique<World>(options.world)),
      it_(nh) {
  if (options_.start_time < path_.start_time() || options_.start_time > path_.end_time()) {
    throw std::invalid_argument(
        "start_time " + std::to_string(options_.start_time) + " s is outside the flight path (" +
        std::to_string(path_.start_time()) + " to " + std::to_string(path_.end_time()) + " s)");
  }
  if (!(options_.stamp_offset + path_.start_time() > 0.0)) {
    throw std::invalid_argument(
        "stamp_offset + path start must be positive: stamps of 0 or less are not valid");
  }
  left_pub_ = it_.advertiseCamera("stereo/left/image_rect", 2);
  right_pub_ = it_.advertiseCamera("stereo/right/image_rect", 2);
  if (options_.publish_labels) {
    left_label_pub_ = it_.advertise("stereo/left/label", 2);
    right_label_pub_ = it_.advertise("stereo/right/label", 2);
  }
  joint_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (options_.lockstep) {
    estimate_sub_ = nh_.subscribe("aar/pose_estimate", 10, &SimNode::OnEstimate, this);
  }
  // The receiver model at truth, for rviz: latched, locked to the receiver_truth frame.
  marker_pub_ = nh_.advertise<visualization_msgs::Marker>("sim/receiver_model", 1, true);
  visualization_msgs::Marker marker;
  marker.header.frame_id = "receiver_truth";
  marker.ns = "receiver_truth";
  marker.type = visualization_msgs::Marker::MESH_RESOURCE;
  marker.mesh_resource =
      "file://" + std::filesystem::absolute(options_.world.receiver_mesh).string();
  marker.pose.orientation.w = 1.0;
  marker.scale.x = marker.scale.y = marker.scale.z = 1.0;
  marker.color.r = marker.color.g = marker.color.b = 0.8f;
  marker.color.a = 1.0f;
  marker.frame_locked = true;
  marker_pub_.publish(marker);

  const ros::Time now(options_.stamp_offset + path_.start_time());
  const StereoRig& rig = options_.world.rig;
  static_tf_.sendTransform(
      {ToTransformMsg(Eigen::Isometry3d::Identity(), now, "world", "tanker"),
       ToTransformMsg(rig.T_tanker_left_optical, now, "tanker", "stereo_left_optical"),
       ToTransformMsg(rig.T_tanker_right_optical(), now, "tanker", "stereo_right_optical")});
  ROS_INFO_STREAM(
      "sim: " << path_.rows().size() << " path rows over " << path_.end_time() - path_.start_time()
              << " s from " << options_.flight_path << "; renderer "
              << world_->renderer().gl_renderer() << "; "
              << (options_.lockstep ? "lockstep"
                                    : "free-running at " + std::to_string(options_.rate) + " Hz")
              << (options_.world.boom_visible ? "" : "; boom hidden"));
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
  }
  finished_ = true;
  if (options_.shutdown_at_end) ros::requestShutdown();
}

void SimNode::Start() { thread_ = std::thread(&SimNode::Run, this); }

void SimNode::OnEstimate(const aar_msgs::PoseEstimate::ConstPtr& msg) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->header.stamp > last_estimate_stamp_) last_estimate_stamp_ = msg->header.stamp;
  }
  estimate_arrived_.notify_all();
}

void SimNode::Loop() {
  if (options_.wait_for_subscribers) {
    ROS_INFO("sim: waiting for subscribers to both images");
    while (!stop_ && ros::ok() &&
           (left_pub_.getNumSubscribers() == 0 || right_pub_.getNumSubscribers() == 0)) {
      ros::WallDuration(0.05).sleep();
    }
  }
  if (options_.start_delay > 0.0) ros::WallDuration(options_.start_delay).sleep();
  const int path_frames = static_cast<int>(std::floor(
                              (path_.end_time() - options_.start_time) * options_.rate + 1e-9)) +
                          1;
  const int frames =
      options_.max_frames > 0 ? std::min(options_.max_frames, path_frames) : path_frames;
  const auto period = std::chrono::duration<double>(1.0 / options_.rate);
  auto next = std::chrono::steady_clock::now();
  int misses = 0;
  for (int k = 0; k < frames && !stop_ && ros::ok(); ++k) {
    const double t = options_.start_time + k / options_.rate;
    const FlightPathRow row = path_.At(t);
    const BoomPose boom = row.boom.value_or(DefaultBoomPose());
    const ros::Time stamp(options_.stamp_offset + t);
    StereoFrame frame;
    try {
      frame = world_->Render(row, boom, static_cast<uint64_t>(k), options_.publish_labels, false);
    } catch (const std::exception& e) {
      ROS_FATAL_STREAM("sim: rendering frame " << k << " failed: " << e.what());
      break;
    }
    PublishFrame(k, row, boom, frame, stamp);
    if (options_.lockstep) {
      std::unique_lock<std::mutex> lock(mutex_);
      const bool arrived =
          estimate_arrived_.wait_for(lock, std::chrono::duration<double>(options_.lockstep_timeout),
                                     [&] { return stop_ || last_estimate_stamp_ >= stamp; });
      if (!arrived) {
        ++misses;
        ROS_WARN_STREAM("sim: no pose estimate for frame "
                        << k << " (stamp " << stamp << ") within " << options_.lockstep_timeout
                        << " s; going on");
      }
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

  const CameraIntrinsics& k = options_.world.rig.intrinsics;
  std_msgs::Header left, right;
  left.stamp = right.stamp = stamp;
  left.seq = right.seq = static_cast<uint32_t>(index);
  // Both in the left optical frame, ROS's stereo convention: the right camera's P (with
  // Tx = -f * baseline) projects points given in the left camera's frame, and image_geometry
  // (hence stereo_image_proc) asserts the frames are equal. The right camera's own pose is the
  // tf frame stereo_right_optical.
  left.frame_id = right.frame_id = "stereo_left_optical";
  left_pub_.publish(ToImageMsg(frame.left.image, left), ToCameraInfoMsg(k, 0.0, left));
  right_pub_.publish(ToImageMsg(frame.right.image, right),
                     ToCameraInfoMsg(k, -k.fx * options_.world.rig.baseline, right));
  if (options_.publish_labels) {
    left_label_pub_.publish(ToImageMsg(frame.left.label, left));
    right_label_pub_.publish(ToImageMsg(frame.right.label, right));
  }
}

}  // namespace aar_sim
