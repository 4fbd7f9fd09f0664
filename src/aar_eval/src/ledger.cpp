#include "aar_eval/ledger.h"

#include <iomanip>
#include <map>
#include <sstream>

#include "aar_eval/evaluator.h"

namespace aar_eval {
namespace {

constexpr const char* kStages[] = {"stereo", "occlusion", "registration"};
constexpr int kStageCount = 3;

int StageIndex(const std::string& stage) {
  for (int i = 0; i < kStageCount; ++i)
    if (stage == kStages[i]) return i;
  return -1;
}

LedgerEntry FromEstimate(const Estimate& e, const std::vector<StageOutcome>& stages) {
  LedgerEntry entry;
  entry.stage = "registration";
  entry.reason = e.track;
  if (e.valid) {
    entry.outcome = e.track == "rejected" || e.track == "missed" ? "coasted" : "estimated";
    return entry;
  }
  entry.outcome = e.track == "lost" ? "lost" : "no_pose";
  for (const StageOutcome& s : stages)
    if (s.stage == "registration" && s.dropped) entry.detail = s.detail;
  return entry;
}

// No estimate came: the first drop reported, else where the frame was last seen.
LedgerEntry Unestimated(const std::vector<StageOutcome>& stages) {
  LedgerEntry entry;
  entry.outcome = "dropped";
  int furthest = -1;
  for (const StageOutcome& s : stages) {
    if (s.dropped) {
      entry.stage = s.stage;
      entry.reason = s.reason;
      entry.detail = s.detail;
      return entry;
    }
    furthest = std::max(furthest, StageIndex(s.stage));
  }
  if (furthest < 0) {
    entry.stage = "stereo";
    entry.reason = "never_paired";
    entry.detail = "no stage reported it: stereo never had its two images and camera infos";
    return entry;
  }
  entry.reason = "queue";
  entry.stage = furthest + 1 < kStageCount ? kStages[furthest + 1] : "eval";
  entry.detail = std::string(kStages[furthest]) + " passed it on; " + entry.stage +
                 " never reported it (lost unseen in its subscriber queue)";
  return entry;
}

}  // namespace

LedgerEntry ClassifyFrame(const Estimate* estimate, const std::vector<StageOutcome>& stages,
                          const std::string& no_truth) {
  if (!no_truth.empty()) return {0, 0.0, "dropped", "eval", "no_truth", no_truth};
  return estimate ? FromEstimate(*estimate, stages) : Unestimated(stages);
}

bool IsFinal(const StageOutcome& outcome) {
  // A further rig's drop (RIG/stereo) leaves the frame to registration, which has the others.
  return outcome.dropped && outcome.stage != "registration" &&
         outcome.stage.find('/') == std::string::npos;
}

std::string LedgerCsvHeader() { return "t,stamp,outcome,stage,reason,detail"; }

std::string LedgerCsvRow(const LedgerEntry& e) {
  std::string detail = e.detail;
  for (size_t i = 0; (i = detail.find('"', i)) != std::string::npos; i += 2) detail.insert(i, "\"");
  std::ostringstream s;
  s << std::setprecision(17) << e.t << ',' << e.stamp_ns / 1000000000 << '.' << std::setw(9)
    << std::setfill('0') << e.stamp_ns % 1000000000 << ',' << e.outcome << ',' << e.stage << ','
    << e.reason << ",\"" << detail << '"';
  return s.str();
}

std::string LedgerSummary(const std::vector<LedgerEntry>& entries) {
  std::map<std::string, int> outcomes;
  std::map<std::string, int> drops;  // "stage reason"
  for (const LedgerEntry& e : entries) {
    ++outcomes[e.outcome];
    if (e.outcome == "dropped") ++drops[e.stage + " " + e.reason];
  }
  std::ostringstream s;
  s << entries.size() << " frames: " << outcomes["estimated"] << " estimated, "
    << outcomes["coasted"] << " coasted, " << outcomes["lost"] << " lost, " << outcomes["no_pose"]
    << " no pose, " << outcomes["dropped"] << " dropped";
  if (!drops.empty()) {
    s << " (";
    bool first = true;
    for (const auto& [where, n] : drops) {
      s << (first ? "" : ", ") << where << ' ' << n;
      first = false;
    }
    s << ')';
  }
  return s.str();
}

}  // namespace aar_eval
