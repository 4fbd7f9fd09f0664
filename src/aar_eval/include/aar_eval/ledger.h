#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aar_eval {

struct Estimate;

// What one stage said about one frame (aar_msgs/FrameOutcome without ROS).
struct StageOutcome {
  std::string stage;  // "stereo", "occlusion", "registration"
  bool dropped = false;
  std::string reason;  // dropped: a key (sync_mismatch, ahead, out_of_order, superseded, ...)
  std::string detail;
};

// A frame's one outcome in the ledger (docs/RELIABILITY.md, Frame ledger).
struct LedgerEntry {
  int64_t stamp_ns = 0;
  double t = 0.0;  // [s] path time
  // estimated, coasted (the tracker's prediction: registration rejected or missing), lost (the
  // track lost, no pose), no_pose (registration gave none), dropped (not estimated: `stage` and
  // `reason` say where and why).
  std::string outcome;
  std::string stage, reason, detail;
};

// The outcome of a frame from its estimate (nullptr: none came) and what the stages reported.
// A frame that a stage passed on and the next stage never reported was lost unseen in that
// stage's subscriber queue (reason "queue"); one no stage reported never became a pair in stereo
// (reason "never_paired"). `no_truth` (eval could not score it): dropped by eval, "no_truth".
LedgerEntry ClassifyFrame(const Estimate* estimate, const std::vector<StageOutcome>& stages,
                          const std::string& no_truth);

// Whether this stage report settles the frame: a drop by any stage but registration, whose
// drops ("no_pose") come with an estimate, and but a further rig's (RIG/stereo, RIG/occlusion:
// registration still answers from the other rigs).
bool IsFinal(const StageOutcome& outcome);

std::string LedgerCsvHeader();                       // t,stamp,outcome,stage,reason,detail
std::string LedgerCsvRow(const LedgerEntry& entry);  // detail quoted as CSV quotes it
// "N frames: a estimated, b coasted, c lost, d no pose, e dropped (stereo sync_mismatch 2, ...)"
std::string LedgerSummary(const std::vector<LedgerEntry>& entries);

}  // namespace aar_eval
