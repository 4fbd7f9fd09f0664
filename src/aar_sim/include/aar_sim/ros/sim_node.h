#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <aar_msgs/PoseEstimate.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/publisher_check.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "aar_sim/flight_path.h"
#include "aar_sim/turbulence.h"
#include "aar_sim/world.h"

namespace aar_sim {

// A rig beyond the first: rendered every frame and published in its own namespace.
struct NamedRig {
  std::string name;  // namespace NAME/{left,right}/..., frames NAME_{left,right}_optical
  StereoRig rig;     // the world's cameras at its own mount
};

struct SimNodeOptions {
  std::string flight_path;          // required: the receiver's path (CSV)
  WorldOptions world;               // models, rig (the first: `stereo`), renderer, boom visibility
  std::vector<NamedRig> more_rigs;  // ~rigs after `stereo` (default: none)
  double rate = 10.0;               // [Hz] frames per second of path time
  double start_time = 0.0;          // [s] path time of the first frame
  int max_frames = 0;               // 0: to the end of the path
  bool lockstep = false;            // wait for /aar/pose_estimate of each frame before the next
  double lockstep_timeout = 5.0;    // [s wall] then go on and count a miss
  // Lockstep: the node whose estimates are the go-ahead (the registration's manager or node;
  // empty: the first publisher heard). Another node linked to the topic, whatever caller id it
  // writes, stops the frame loop (FATAL, naming it): its estimates could not be told apart.
  std::string estimate_publisher;
  // Free-running: seconds of path time per wall second (1: real time; below 1 the flight and its
  // clock run slower, for a machine or a build that cannot keep up).
  double realtime_factor = 1.0;
  bool wait_for_subscribers =
      false;                 // hold frame 0 until both images of every rig have a subscriber
  double start_delay = 0.0;  // [s wall] then wait this long (other listeners connecting)
  bool publish_labels =
      false;  // also /stereo/{left,right}/label (mono8: 0 sky, 1 receiver, 2 boom)
  // Also /sim/visibility (aar_msgs/Visibility): how much of the receiver the boom hides in each
  // camera (World::MeasureVisibility: one more label render per camera). Default: on in lockstep.
  bool measure_visibility = false;
  bool shutdown_at_end = false;  // end the process after the last frame (experiments; in a
                                 // nodelet manager this ends the manager)
  double stamp_offset = 1.0;     // [s] stamp = offset + path time; stamp 0 means "latest" to tf
  TurbulenceOptions turbulence;  // gusts moving the receiver and the boom (default: none)
};

// Reads ~parameters; throws std::invalid_argument naming a missing required parameter, a bad
// value or an unknown parameter (a typo would otherwise be ignored silently).
SimNodeOptions LoadSimNodeOptions(const ros::NodeHandle& private_nh);
SimNodeOptions LoadSimNodeOptions(aar_ros_common::ParamReader& params);

// Renders the flight path frame by frame and publishes images, camera infos, joint states, truth
// tf and /clock with one stamp per frame.
class SimNode {
 public:
  // Throws aar_geometry::LoadError (models, path) or RenderError (no EGL) before publishing.
  SimNode(ros::NodeHandle nh, const SimNodeOptions& options);
  ~SimNode();

  void Start();  // starts the frame loop on its own thread
  bool finished() const { return finished_; }
  bool failed() const { return failed_; }  // the frame loop stopped on an error (logged FATAL)

 private:
  // The constructor's steps.
  void CheckStartTime() const;  // start_time within the path, stamps positive
  void Advertise();
  void PublishStatic();  // the receiver's marker and the cameras' static transforms
  void LogSettings() const;
  void LogRealism() const;  // the sun, the propellers and the turbulence, when on

  void Run();  // the thread: Loop, guarded
  void Loop();
  // Loop's steps.
  void WaitToStart() const;  // for both images' subscribers (when asked to), then start_delay
  int FrameCount() const;    // the path's frames from start_time at the rate, at most `frames`
  // Rig `rig`'s pair of frame k (0: the world's own rig).
  StereoFrame RenderFrame(int k, double t, const FlightPathRow& row, const BoomPose& boom,
                          size_t rig = 0);
  bool WaitForEstimate(int k, const ros::Time& stamp);  // lockstep; false: timed out (warned)
  // /sim/visibility of the frame (measure_visibility), before its images; a further rig's on
  // /sim/NAME/visibility.
  void PublishVisibility(const ros::Publisher& pub, const std::array<ViewVisibility, 2>& views,
                         const ros::Time& stamp);
  void PublishFrame(int index, const FlightPathRow& row, const BoomPose& boom,
                    const StereoFrame& frame, const ros::Time& stamp);
  // A rig's visibility (measure_visibility), then its pair, camera infos and labels (rig 0:
  // `stereo`; then options_.more_rigs).
  void PublishImages(size_t rig, int index, const StereoFrame& frame, const ros::Time& stamp);
  // Every further rig's frame k, rendered and published.
  void PublishMoreRigs(int k, double t, const FlightPathRow& row, const BoomPose& boom,
                       const ros::Time& stamp);
  void OnEstimate(const ros::MessageEvent<aar_msgs::PoseEstimate const>& event);
  // Why estimates cannot be trusted ("" if they can): another node linked to the topic.
  std::string Intrusion(const std::string& caller);
  // The path's row and boom pose at t [s] (the boom from the row, else DefaultBoomPose()) with
  // the turbulence applied: what is rendered and published as truth.
  std::pair<FlightPathRow, BoomPose> StateAt(double t) const;

  ros::NodeHandle nh_;
  SimNodeOptions options_;
  std::unique_ptr<World> world_;  // before path_: the path is checked against its boom model
  FlightPath path_;
  Turbulence turbulence_;  // over the path's span
  image_transport::ImageTransport it_;
  // Per rig (0: `stereo`, then options_.more_rigs): its images, camera infos, labels, visibility.
  struct RigPublishers {
    std::string name, left_frame, right_frame;
    const StereoRig* rig = nullptr;
    image_transport::CameraPublisher left, right;
    image_transport::Publisher left_label, right_label;
    ros::Publisher visibility;
  };
  std::vector<RigPublishers> rigs_;
  ros::Publisher joint_pub_, clock_pub_, marker_pub_;
  ros::Subscriber estimate_sub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;

  std::mutex mutex_;
  std::condition_variable estimate_arrived_;
  ros::Time last_estimate_stamp_;
  std::optional<aar_ros_common::PublisherCheck> check_;  // once the publisher is known
  std::string intrusion_;                                // set once: the frame loop stops on it
  std::atomic<bool> stop_{false}, finished_{false}, failed_{false};
  std::thread thread_;
};

}  // namespace aar_sim
