#include "aar_stereo/ros/stereo_node.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/receiver_params.h>
#include <aar_ros_common/robot_description.h>
#include <aar_ros_common/start_count.h>
#include <aar_ros_common/tf_bridge.h>

#include <sensor_msgs/PointCloud2.h>
#include <stereo_msgs/DisparityImage.h>

#include "aar_stereo/ros/conversions.h"

namespace aar_stereo {

StereoNode::StereoNode(ros::NodeHandle nh, ros::NodeHandle private_nh,
                       const StereoNodeOptions& options)
    : nh_(nh),
      private_nh_(private_nh),
      options_(options),
      reconfigure_(private_nh),
      diagnostics_(nh, private_nh),
      ledger_(nh, "stereo", options.common.rig) {
  if (options_.roi.enabled) {
    const StereoRoiOptions& roi = options_.roi;
    receiver_box_ = aar_description::LoadReceiverMesh(roi.receiver).Bounds();  // throws: fatal
    if (roi.include_boom) {
      try {
        boom_ = aar_ros_common::LoadRobotDescription(nh_, options_.common.robot_description);
      } catch (const aar_geometry::LoadError&) {  // a URDF that is there but refused: as it says
        throw;
      } catch (const std::runtime_error& e) {  // none: fatal, the region would cut its points
        throw std::invalid_argument(std::string("~roi_include_boom needs the boom's URDF: ") +
                                    e.what());
      }
    }
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
    // Estimates are published outside the stereo namespace: an absolute name (remappable).
    estimates_ = std::make_unique<aar_ros_common::EstimateListener>(nh_, "/aar/pose_estimate",
                                                                    options_.common.frames.tanker);
  }
  // Process-wide: in a nodelet manager it applies to every OpenCV call of every nodelet.
  if (options_.opencv_threads >= 0) cv::setNumThreads(options_.opencv_threads);
  stage_ = std::make_unique<aar_ros_common::Stage<Pair>>(
      options_.newest_wins, [this](Pair& p) { Match(p); },
      [](const Pair& p) { return p.left->header.stamp; }, ledger_,
      aar_ros_common::Stage<Pair>::Names{"stereo", "pair", "matching"});
  reconfigure_.setCallback(
      [this](StereoConfig& config, uint32_t level) { OnReconfigure(config, level); });
  if (options_.approximate_sync) {
    approximate_ = std::make_unique<message_filters::Synchronizer<ApproximatePolicy>>(
        ApproximatePolicy(options_.queue_size), left_sub_, left_info_sub_, right_sub_,
        right_info_sub_);
    approximate_->registerCallback(&StereoNode::OnFrame, this);
  } else {
    exact_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(
        ExactPolicy(options_.queue_size), left_sub_, left_info_sub_, right_sub_, right_info_sub_);
    exact_->registerCallback(&StereoNode::OnFrame, this);
    // A tuple dropped incomplete: some halves of a pair never came (or came too late).
    exact_->registerDropCallback(&StereoNode::OnUnpaired, this);
  }
  // Arrival bookkeeping for the "stamps never match" report.
  auto note = [this](int i, const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(input_mutex_);
    last_stamp_[i] = stamp;
    last_arrival_[i] = ros::WallTime::now();
  };
  left_sub_.registerCallback(boost::function<void(const Image::ConstPtr&)>(
      [note](const Image::ConstPtr& m) { note(0, m->header.stamp); }));
  left_info_sub_.registerCallback(boost::function<void(const Info::ConstPtr&)>(
      [note](const Info::ConstPtr& m) { note(1, m->header.stamp); }));
  right_sub_.registerCallback(boost::function<void(const Image::ConstPtr&)>(
      [note](const Image::ConstPtr& m) { note(2, m->header.stamp); }));
  right_info_sub_.registerCallback(boost::function<void(const Info::ConstPtr&)>(
      [note](const Info::ConstPtr& m) { note(3, m->header.stamp); }));

  // Lazy: subscribe to the cameras only while someone listens to an output.
  auto connect = [this](const ros::SingleSubscriberPublisher&) { Connect(); };
  std::lock_guard<std::mutex> lock(connect_mutex_);
  disparity_pub_ = nh_.advertise<stereo_msgs::DisparityImage>("disparity", 1, connect, connect);
  points_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("points2", 1, connect, connect);

  diagnostics_.setHardwareID("stereo pair " + nh_.resolveName("left") + ", " +
                             nh_.resolveName("right"));
  diagnostics_.add("stereo", this, &StereoNode::Diagnose);
  input_timer_ = nh_.createWallTimer(ros::WallDuration(2.0), &StereoNode::CheckInputs, this);
  aar_ros_common::AnnounceStart(private_nh_, "stereo");
}

StereoNode::~StereoNode() {
  // Inputs, timer and matching thread first: nothing may run into members being destroyed.
  input_timer_.stop();
  left_sub_.unsubscribe();
  left_info_sub_.unsubscribe();
  right_sub_.unsubscribe();
  right_info_sub_.unsubscribe();
  stage_->Stop();
}

void StereoNode::Connect() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  const bool wanted = disparity_pub_.getNumSubscribers() > 0 || points_pub_.getNumSubscribers() > 0;
  if (wanted && !subscribed_) {
    const uint32_t q = stage_->queue(static_cast<uint32_t>(options_.queue_size));
    left_sub_.subscribe(nh_, "left/image_rect", q);
    left_info_sub_.subscribe(nh_, "left/camera_info", q);
    right_sub_.subscribe(nh_, "right/image_rect", q);
    right_info_sub_.subscribe(nh_, "right/camera_info", q);
    {
      std::lock_guard<std::mutex> input(input_mutex_);
      last_frame_ = ros::WallTime::now();
    }
    subscribed_ = true;
  } else if (!wanted && subscribed_) {
    left_sub_.unsubscribe();
    left_info_sub_.unsubscribe();
    right_sub_.unsubscribe();
    right_info_sub_.unsubscribe();
    subscribed_ = false;
  }
}

void StereoNode::OnReconfigure(StereoConfig& config, uint32_t) {
  try {
    const StereoConfig asked = config;
    auto processor = std::make_unique<StereoProcessor>(ToStereoOptions(config));
    if (asked.block_size != config.block_size || asked.prefilter_size != config.prefilter_size ||
        asked.num_disparities != config.num_disparities || asked.organized != config.organized) {
      ROS_WARN_STREAM("stereo: settings adjusted to what the matcher takes: block_size "
                      << asked.block_size << " -> " << config.block_size << ", prefilter_size "
                      << asked.prefilter_size << " -> " << config.prefilter_size
                      << ", num_disparities " << asked.num_disparities << " -> "
                      << config.num_disparities << ", organized " << asked.organized << " -> "
                      << config.organized);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    processor_ = std::move(processor);
  } catch (const std::exception& e) {
    ROS_ERROR_STREAM("stereo: settings rejected, keeping the previous ones: " << e.what());
  }
}

void StereoNode::OnFrame(const Image::ConstPtr& left, const Info::ConstPtr& left_info,
                         const Image::ConstPtr& right, const Info::ConstPtr& right_info) {
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    last_frame_ = ros::WallTime::now();
  }
  const ros::Time& stamp = left->header.stamp;
  // Halves from different instants (approximate sync, one camera lagging): the disparity
  // would mix two poses of the receiver. Exact sync pairs equal stamps only.
  const ros::Time first = std::min({stamp, left_info->header.stamp, right->header.stamp,
                                    right_info->header.stamp}),
                  last = std::max({stamp, left_info->header.stamp, right->header.stamp,
                                   right_info->header.stamp});
  if ((last - first).toSec() > options_.max_pair_skew) {
    const uint64_t dropped = ledger_.Dropped(
        stamp, "sync_mismatch",
        "halves " + std::to_string((last - first).toSec()) + " s apart, more than max_pair_skew");
    std::ostringstream s;
    s << "stereo: " << left_sub_.getTopic() << " " << stamp << " and " << right_sub_.getTopic()
      << " " << right->header.stamp << " (camera infos " << left_info->header.stamp << ", "
      << right_info->header.stamp << ") are " << (last - first).toSec()
      << " s apart, more than max_pair_skew (" << options_.max_pair_skew
      << " s): pair dropped, is one camera lagging? " << dropped << " dropped for sync so far";
    if (errors_.ShouldLog(s.str())) ROS_WARN_STREAM(s.str());
    return;
  }
  // A pair stamped far ahead of the clock would become the last one taken, and every pair
  // after it would be out of order until the clock passed it. Dropped, named.
  if (const std::string ahead = StampAhead(stamp); !ahead.empty()) {
    const uint64_t dropped = ledger_.Dropped(stamp, "ahead", ahead);
    const std::string what = "stereo: pair on " + left_sub_.getTopic() + " and " +
                             right_sub_.getTopic() + " dropped: " + ahead;
    if (errors_.ShouldLog(what)) ROS_WARN_STREAM(what << " (" << dropped << " dropped so far)");
    return;
  }
  // A pair older than the last one taken came late (out of order): its cloud would reach the
  // stages after a newer one's. Dropped, named with both stamps.
  if (const std::string late = order_.Check(stamp, ros::Time::now()); !late.empty()) {
    ledger_.Dropped(stamp, "out_of_order", late);
    const std::string what = "stereo: pair on " + left_sub_.getTopic() + " and " +
                             right_sub_.getTopic() + " dropped: " + late;
    if (errors_.ShouldLog(what))
      ROS_WARN_STREAM(what << " (" << order_.dropped() << " dropped so far)");
    return;
  }
  last_taken_ = stamp;
  stage_->Hand(Pair{left, right, left_info, right_info});
}

std::string StereoNode::StampAhead(const ros::Time& stamp) const {
  const ros::Time now = ros::Time::now();
  // Under sim time the clock is 0 until the first /clock: nothing to compare with yet.
  if (now.isZero() || (stamp - now).toSec() <= options_.max_stamp_lead) return "";
  // A clock that lags the data is not enough (its callback queued behind busy ones in a fast
  // replay): the pair must also be that far ahead of the last pair taken.
  if (!last_taken_.isZero() && (stamp - last_taken_).toSec() <= options_.max_stamp_lead) return "";
  std::ostringstream s;
  s << "stamp " << stamp << " is " << (stamp - now).toSec() << " s ahead of the clock (" << now
    << "; max_stamp_lead " << options_.max_stamp_lead << " s)";
  return s.str();
}

void StereoNode::OnUnpaired(const Image::ConstPtr& left, const Info::ConstPtr& left_info,
                            const Image::ConstPtr& right, const Info::ConstPtr& right_info) {
  std::string came, missing;
  auto note = [&](bool present, const std::string& what) {
    std::string& list = present ? came : missing;
    list += (list.empty() ? "" : ", ") + what;
  };
  note(left != nullptr, "left image");
  note(left_info != nullptr, "left camera info");
  note(right != nullptr, "right image");
  note(right_info != nullptr, "right camera info");
  ros::Time stamp;
  if (left)
    stamp = left->header.stamp;
  else if (left_info)
    stamp = left_info->header.stamp;
  else if (right)
    stamp = right->header.stamp;
  else if (right_info)
    stamp = right_info->header.stamp;
  const std::string detail = came + " came, no " + missing + " with its stamp";
  const uint64_t dropped = ledger_.Dropped(stamp, "sync_mismatch", detail);
  const std::string what = "stereo: frame " + std::to_string(stamp.toSec()) +
                           " dropped: " + detail + " (exact sync): are the cameras synchronised?";
  if (errors_.ShouldLog(what))
    ROS_WARN_STREAM(what << " (" << dropped << " dropped for sync so far)");
}

void StereoNode::Match(Pair& pair) {
  const Image::ConstPtr& left = pair.left;
  const Image::ConstPtr& right = pair.right;
  const Info::ConstPtr& left_info = pair.left_info;
  const Info::ConstPtr& right_info = pair.right_info;
  // Behind real time: a pair that waited too long is dropped, so that the next one is fresh.
  if (options_.max_frame_age > 0.0) {
    const double age = (ros::Time::now() - left->header.stamp).toSec();
    if (age > options_.max_frame_age) {
      const uint64_t dropped =
          ledger_.Dropped(left->header.stamp, "stale",
                          "waited " + std::to_string(age) + " s, more than max_frame_age");
      ROS_WARN_STREAM_THROTTLE(5.0, "stereo: dropping pairs that waited longer than max_frame_age ("
                                        << options_.max_frame_age << " s; this one " << age
                                        << " s): the graph is behind real time; " << dropped
                                        << " dropped so far");
      return;
    }
  }
  try {
    const StereoGeometry geometry = ToStereoGeometry(
        *left_info, *right_info, left_info_sub_.getTopic(), right_info_sub_.getTopic());
    if (!options_.rectified_upstream) WarnIfDistorted(*left_info, *right_info);
    const cv::Mat l = ToMono8(*left, "left"), r = ToMono8(*right, "right");
    std::lock_guard<std::mutex> lock(mutex_);
    if (!processor_) throw std::runtime_error("no matcher settings");
    std::string why;
    FrameRegion region;
    try {
      region = Roi(left->header, geometry, &why);
    } catch (const std::exception& e) {  // a region of interest is an optimisation: match all
      why = e.what();
    }
    const std::optional<cv::Rect>& roi = region.roi;
    const StereoResult result = processor_->Process(l, r, geometry, roi, region.zones);
    std_msgs::Header header = left->header;
    if (disparity_pub_.getNumSubscribers() > 0) {
      disparity_pub_.publish(
          ToDisparityMsg(result, processor_->options(), geometry, result.valid_window, header));
    }
    // Shared pointers: nodelets in the same manager receive the message without a copy.
    if (points_pub_.getNumSubscribers() > 0)
      points_pub_.publish(ToPointCloud2Msg(result.cloud, header));
    ledger_.Passed(header.stamp);
    ++frames_;
    {
      std::lock_guard<std::mutex> stats(stats_mutex_);
      last_timings_ = result.timings;
      last_points_ = result.cloud.xyz.size();
      roi_frames_ += roi.has_value();
      last_roi_fraction_ =
          roi ? static_cast<double>(roi->area()) / (geometry.width * geometry.height) : 1.0;
      last_roi_why_ = why;
      if (result.sparse) last_samples_ = result.samples;
    }
    ROS_DEBUG_STREAM("stereo: frame " << header.stamp << ": " << result.cloud.xyz.size()
                                      << " points; matching " << result.timings.matching_ms
                                      << " ms, reprojection " << result.timings.reprojection_ms
                                      << " ms, decimation " << result.timings.decimation_ms
                                      << " ms");
    ROS_INFO_STREAM_THROTTLE(
        10.0, "stereo: " << frames_ << " frames; last: " << result.cloud.xyz.size() << " points in "
                         << result.timings.total_ms << " ms"
                         << (roi ? ", matched in a region of interest" : "")
                         << (why.empty() ? "" : " (whole image: " + why + ")"));
  } catch (const std::exception& e) {
    ++skipped_;
    ledger_.Dropped(left->header.stamp, "error", e.what());
    {
      std::lock_guard<std::mutex> stats(stats_mutex_);
      last_error_ = e.what();
    }
    // Throttled per reason, not per call site: a new problem is reported at once.
    if (errors_.ShouldLog(e.what()))
      ROS_ERROR_STREAM("stereo: frame " << left->header.stamp << " skipped: " << e.what());
  }
}

// image_rect with a distorted camera info and nothing rectifying in front: the images are most
// likely raw (a driver's image_raw remapped), and matching them gives wrong depths at the edges.
// The pair is still processed (a calibration may carry D for rectified images); the warning,
// throttled, names the topics and the coefficients.
void StereoNode::WarnIfDistorted(const Info& left, const Info& right) {
  const std::string l = DescribeDistortion(left), r = DescribeDistortion(right);
  if (l.empty() && r.empty()) return;
  ++distorted_;
  ROS_WARN_STREAM_THROTTLE(
      10.0, "stereo: camera infos with distortion on image_rect input: "
                << (l.empty() ? "" : left_info_sub_.getTopic() + " " + l)
                << (l.empty() || r.empty() ? "" : "; ")
                << (r.empty() ? "" : right_info_sub_.getTopic() + " " + r)
                << ". aar_stereo needs rectified images: are raw images fed as image_rect? Put "
                   "image_proc's rectify in front (pipeline.launch rectify:=true) and set "
                   "~rectified_upstream true; "
                << distorted_ << " such pairs so far");
}

std::optional<Eigen::Isometry3d> StereoNode::Transform(const std::string& target,
                                                       const std::string& source,
                                                       const ros::Time& stamp, std::string* why) {
  return aar_ros_common::LookupTransformOrLatest(
      *tf_buffer_, target, source, stamp, options_.common.tf_timeout,
      options_.common.tf_fallback_age, "the images' stamp", why);
}

FrameRegion StereoNode::Roi(const std_msgs::Header& header, const StereoGeometry& geometry,
                            std::string* why) {
  if (!options_.roi.enabled) return {};
  const StereoRoiOptions& o = options_.roi;
  // In lockstep the previous frame's estimate is on its way; waiting for it makes runs repeatable.
  if (previous_stamp_ && o.estimate_wait > 0.0 && header.stamp > *previous_stamp_)
    estimates_->WaitFor(*previous_stamp_, o.estimate_wait);
  previous_stamp_ = header.stamp;
  const auto predicted = estimates_->Predict(header.stamp, options_.common.estimate_max_age);
  if (!predicted || !predicted->tracking) {
    *why = "no tracked estimate within estimate_max_age";
    return {};
  }
  const auto T_tanker_optical =
      Transform(options_.common.frames.tanker, header.frame_id, header.stamp, why);
  if (!T_tanker_optical) return {};
  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical->inverse();
  const std::vector<Eigen::Vector3d> receiver =
      BoxCorners(receiver_box_, T_optical_tanker * predicted->T_tanker_receiver, o.receiver_margin);
  std::vector<Eigen::Vector3d> boom;
  if (boom_) {
    std::map<std::string, Eigen::Isometry3d> T_tanker_links;
    for (const auto& link : boom_->links) {
      const auto T = Transform(options_.common.frames.tanker, link.name, header.stamp, why);
      if (!T) return {};
      T_tanker_links[link.name] = *T;
    }
    const auto mesh =
        aar_geometry::RobotMesh(*boom_, T_tanker_links, aar_geometry::GeometryKind::kCollision);
    for (const auto& v : mesh.vertices) boom.push_back(T_optical_tanker * v);
  }
  FrameRegion region;
  if (processor_->options().matcher == Matcher::kSparse) {
    // Samples on the receiver only (the boom's points are culled downstream); searched up to the
    // nearest of the receiver's box and, where the boom crosses it, of the boom.
    region.roi = ProjectedRoi(receiver, geometry, o.margin);
    region.zones.push_back({*region.roi, MaxDisparity(receiver, geometry)});
    if (!boom.empty())
      region.zones.push_back(
          {ProjectedRoi(boom, geometry, o.margin), MaxDisparity(boom, geometry)});
    return region;
  }
  std::vector<Eigen::Vector3d> bounds = receiver;
  bounds.insert(bounds.end(), boom.begin(), boom.end());
  region.roi = ProjectedRoi(bounds, geometry, o.margin);
  return region;
}

void StereoNode::CheckInputs(const ros::WallTimerEvent&) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const ros::WallDuration window(4.0);
  bool all_arriving = true;
  for (const auto& t : last_arrival_) all_arriving &= !t.isZero() && now - t < window;
  if (all_arriving && now - last_frame_ > window) {
    ROS_ERROR_STREAM_THROTTLE(
        10.0, "stereo: images and camera infos arrive but their stamps never match "
                  << "(left image " << last_stamp_[0] << ", left info " << last_stamp_[1]
                  << ", right image " << last_stamp_[2] << ", right info " << last_stamp_[3]
                  << "); exact sync needs all four equal: set ~approximate_sync true for "
                     "cameras that are not synchronised");
  }
  diagnostics_.update();
}

void StereoNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  // Judged on the frames since the previous report, so a warning clears once inputs are good.
  const uint64_t frames = frames_ - reported_frames_, skipped = skipped_ - reported_skipped_;
  reported_frames_ = frames_;
  reported_skipped_ = skipped_;
  if (skipped > 0 && frames == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "every recent frame skipped: " + last_error_);
  } else if (skipped > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "frames skipped, last because: " + last_error_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, frames > 0 ? "processing" : "no input");
  }
  status.add("frames", static_cast<uint64_t>(frames_));
  // Drops by reason (stale, out_of_order, sync_mismatch, superseded, ahead, error): the ledger's.
  for (const auto& [key, n] : ledger_.Counts()) status.add("ledger: " + key, n);
  if (!options_.rectified_upstream)
    status.add("pairs with distorted camera infos (unrectified?)",
               static_cast<uint64_t>(distorted_));
  status.add("points (last frame)", last_points_);
  status.add("matching [ms]", last_timings_.matching_ms);
  status.add("reprojection [ms]", last_timings_.reprojection_ms);
  status.add("decimation [ms]", last_timings_.decimation_ms);
  status.add("total [ms]", last_timings_.total_ms);
  if (options_.roi.enabled) {
    status.add("frames matched in a region of interest", roi_frames_);
    status.add("matched fraction of the image (last frame)", last_roi_fraction_);
    status.add("why the last frame was matched whole", last_roi_why_);
  }
  if (last_samples_.stride > 0) {
    status.add("sparse: grid stride [px] (last frame)", last_samples_.stride);
    status.add("sparse: samples (last frame)", last_samples_.samples);
    status.add("sparse: untextured / ambiguous / at the predicted bound / left-right refused",
               std::to_string(last_samples_.untextured) + " / " +
                   std::to_string(last_samples_.ambiguous) + " / " +
                   std::to_string(last_samples_.at_bound) + " / " +
                   std::to_string(last_samples_.inconsistent));
  }
}

}  // namespace aar_stereo
