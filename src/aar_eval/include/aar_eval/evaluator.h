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

#include "aar_eval/ledger.h"
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
  // Integrity (aar_msgs/PoseEstimate): the publisher's alert (do not use the pose), the
  // protection levels that bound this pose's error at the publisher's integrity risk, and the
  // alert limits of its phase. Levels and limits of 0: the publisher gives none.
  bool alert = false;
  double protection_level_position = 0.0;  // [m] bound on the 3D position error
  double protection_level_attitude = 0.0;  // [deg] bound on the rotation angle of the error
  double alert_limit_position = 0.0;       // [m]
  double alert_limit_attitude = 0.0;       // [deg]
};

// One camera's view of the receiver in a frame (aar_msgs/Visibility without ROS).
struct CameraVisibility {
  int silhouette_px = 0;  // the receiver drawn alone, inside the view
  int visible_px = 0;     // of those, not covered by the boom
};

// One frame whose outcome is final, in stamp order.
struct SettledFrame {
  int64_t stamp_ns = 0;
  FrameRecord record;    // estimated or missed
  std::string no_truth;  // set when truth was missing: the frame is left out of the records
  LedgerEntry ledger;    // its one outcome in the frame ledger
  // "eval: frame k of N, 50.0 m (region B): error 0.123 m; running mean ..." for every tenth
  // frame and every miss; empty for the others.
  std::string progress;
};

// The truth T_tanker_receiver at a stamp, or nullopt with `error` saying why.
using TruthLookup =
    std::function<std::optional<Eigen::Isometry3d>(int64_t stamp_ns, std::string* error)>;

// Whether the truth at a stamp has arrived (a frame waits for it before it settles).
using TruthReady = std::function<bool(int64_t stamp_ns)>;

// Pairs each announced frame with its estimate and the truth, and decides when a frame is
// settled: when its estimate came, a stage reported dropping it, or a later announced frame's
// estimate came (estimates come in stamp order: this one's was lost), and its truth is there; or,
// failing all, `settle_after` seconds after it was announced: then it is a miss, and the stages'
// reports say where it was lost (the frame ledger). Frames settle in stamp order. Time, not a
// count of later frames: a busy machine delays estimates without losing them. ROS-free; not
// thread-safe.
class Evaluator {
 public:
  // `stamp_offset` [s]: the simulator's stamp = offset + path time. `expected_frames`: N in the
  // progress lines (0: unknown). `settle_after` [s, the clock of `now_s`]: the longest a frame
  // waits for its estimate.
  explicit Evaluator(double stamp_offset = 1.0, int expected_frames = 0, double settle_after = 10.0)
      : stamp_offset_(stamp_offset),
        expected_frames_(expected_frames),
        settle_after_(settle_after) {}

  enum class FrameStatus { kNew, kRepeat, kOlder };
  // A frame was announced (its camera info) at `now_s`. kOlder frames are ignored (the clock
  // jumped).
  FrameStatus AddFrame(int64_t stamp_ns, double now_s = 0.0);
  // False when its frame is already settled (the estimate came too late and is ignored).
  bool AddEstimate(int64_t stamp_ns, const Estimate& estimate);
  // A stage's report on a frame; false when the frame is already settled.
  bool AddOutcome(int64_t stamp_ns, const StageOutcome& outcome);
  // The simulator's visibility of the receiver in the views of rig `rig` (0: the first; issue
  // 44); false when the frame is already settled. The frame's record takes the view with the
  // most visible pixels of any rig, and the weaker camera of the rig whose weaker camera sees
  // most (stereo needs both of one rig). From the first one on, a frame waits for its
  // visibility before it settles (or settle_after).
  bool AddVisibility(int64_t stamp_ns, const std::vector<CameraVisibility>& views, size_t rig = 0);

  // The frames that are settled at `now_s`, in stamp order.
  std::vector<SettledFrame> SettleReady(double now_s, const TruthReady& ready,
                                        const TruthLookup& truth);
  // Every frame announced so far (the run is over: what has no estimate now is a miss).
  std::vector<SettledFrame> SettleAll(const TruthLookup& truth);

  const std::vector<FrameRecord>& records() const { return records_; }
  const std::vector<LedgerEntry>& ledger() const { return ledger_; }
  int64_t newest_frame_ns() const { return frames_.empty() ? 0 : frames_.back().stamp_ns; }
  size_t estimates_without_frame() const { return estimates_.size(); }
  int frames_without_truth() const { return no_truth_; }

 private:
  struct Announced {
    int64_t stamp_ns;
    double at_s;  // when it was announced
  };
  bool Resolved(int64_t stamp_ns) const;  // its estimate, a later one, or a final drop came
  SettledFrame SettleFront(const TruthLookup& truth);
  void Score(const Eigen::Isometry3d& T_truth, SettledFrame& s);
  std::string ProgressLine(const FrameRecord& frame) const;  // of the newest record

  double stamp_offset_;
  int expected_frames_;
  double settle_after_;
  std::deque<Announced> frames_;  // announced, not yet settled
  std::set<int64_t> settled_;
  std::map<int64_t, Estimate> estimates_;
  std::map<int64_t, std::vector<StageOutcome>> outcomes_;  // the stages' reports per frame
  // Per frame, until settled: each rig's views.
  std::map<int64_t, std::vector<std::vector<CameraVisibility>>> visibility_;
  bool visibility_seen_ = false;  // a visibility came: the simulator measures it
  std::vector<LedgerEntry> ledger_;
  std::vector<FrameRecord> records_;
  int no_truth_ = 0;
  std::optional<Eigen::Isometry3d> last_estimate_;  // T_tanker_receiver, held through misses
  double position_sum_ = 0.0;  // [m] of the estimated frames' position error norms
  int estimated_ = 0;
};

}  // namespace aar_eval
