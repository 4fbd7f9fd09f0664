#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "aar_eval/tables.h"

namespace aar_eval {

// A pose estimate as the evaluation needs it (aar_msgs/PoseEstimate without ROS).
struct Estimate {
  bool valid = false;  // false: registration gave no pose (a miss)
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  bool converged = false;
  int iterations = 0;
  double rms = 0.0;              // [m]
  double registration_ms = 0.0;  // [ms]
  // [m^2, rad^2] of T_tanker_receiver: position, then rotation (R_truth = Exp(dtheta) R),
  // tanker frame; zero when not estimated.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  std::string track = "off";  // the tracker's outcome by name
};

// One frame whose outcome is final, in stamp order.
struct SettledFrame {
  int64_t stamp_ns = 0;
  FrameRecord record;    // estimated or missed
  std::string no_truth;  // set when truth was missing: the frame is left out of the records
  // "eval: frame k of N, 50.0 m (region B): error 0.123 m; running mean ..." for every tenth
  // frame and every miss; empty for the others.
  std::string progress;
};

// The truth T_tanker_receiver at a stamp, or nullopt with `error` saying why.
using TruthLookup =
    std::function<std::optional<Eigen::Isometry3d>(int64_t stamp_ns, std::string* error)>;

// Pairs each announced frame with its estimate and the truth, and decides when a frame is
// settled: an estimate that has not come when a later frame is settled is a miss. Lockstep
// publishes a frame only after the estimate of the one before (or a timeout); one frame of
// grace covers message ordering. ROS-free; not thread-safe.
class Evaluator {
 public:
  // `stamp_offset` [s]: the simulator's stamp = offset + path time. `expected_frames`: N in the
  // progress lines (0: unknown).
  // `grace_frames`: a frame is settled once this many newer ones were announced (2 in lockstep;
  // in real time, estimates lag several frames).
  explicit Evaluator(double stamp_offset = 1.0, int expected_frames = 0, int grace_frames = 2)
      : stamp_offset_(stamp_offset),
        expected_frames_(expected_frames),
        grace_frames_(grace_frames < 1 ? 1 : grace_frames) {}

  enum class FrameStatus { kNew, kRepeat, kOlder };
  // A frame was announced (its camera info). kOlder frames are ignored (the clock jumped).
  FrameStatus AddFrame(int64_t stamp_ns);
  // False when its frame is already settled (the estimate came too late and is ignored).
  bool AddEstimate(int64_t stamp_ns, const Estimate& estimate);

  // The frames that are settled now: all but the newest `grace_frames` announced ones.
  std::vector<SettledFrame> SettleReady(const TruthLookup& truth);
  // Every frame announced so far (the run is over: what has no estimate now is a miss).
  std::vector<SettledFrame> SettleAll(const TruthLookup& truth);

  const std::vector<FrameRecord>& records() const { return records_; }
  int64_t newest_frame_ns() const { return frames_.empty() ? 0 : frames_.back(); }
  size_t estimates_without_frame() const { return estimates_.size(); }
  int frames_without_truth() const { return no_truth_; }

 private:
  std::vector<SettledFrame> Settle(int64_t before_ns, const TruthLookup& truth);
  std::string ProgressLine(const FrameRecord& frame) const;  // of the newest record

  double stamp_offset_;
  int expected_frames_;
  int grace_frames_;
  std::deque<int64_t> frames_;  // announced, not yet settled
  std::set<int64_t> settled_;
  std::map<int64_t, Estimate> estimates_;
  std::vector<FrameRecord> records_;
  int no_truth_ = 0;
  std::optional<Eigen::Isometry3d> last_estimate_;  // T_tanker_receiver, held through misses
  double position_sum_ = 0.0;  // [m] of the estimated frames' position error norms
  int estimated_ = 0;
};

}  // namespace aar_eval
