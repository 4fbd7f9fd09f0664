#include "aar_eval/evaluator.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include <aar_geometry/pose.h>
#include <aar_geometry/pose_error.h>
#include <Eigen/Cholesky>

namespace aar_eval {
namespace {

// As ros::Time::toSec, so that path times are the same to the last digit.
double ToSec(int64_t stamp_ns) {
  return static_cast<double>(stamp_ns / 1000000000) +
         1e-9 * static_cast<double>(stamp_ns % 1000000000);
}

// The estimate's error against its covariance (NaN when it has none or it is singular).
double Nees(const Eigen::Isometry3d& truth, const Estimate& e) {
  const Eigen::AngleAxisd aa(truth.linear() * e.T_tanker_receiver.linear().transpose());
  Eigen::Matrix<double, 6, 1> d;
  d << truth.translation() - e.T_tanker_receiver.translation(), aa.angle() * aa.axis();
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(e.covariance);
  if (e.covariance.isZero() || ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      !(ldlt.vectorD().minCoeff() > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  return d.dot(ldlt.solve(d));
}

// FrameRecord::error of `estimate` against `truth`.
std::array<double, 6> ErrorComponents(const Eigen::Isometry3d& truth,
                                      const Eigen::Isometry3d& estimate) {
  const aar_geometry::PoseError e = aar_geometry::ComputePoseError(truth, estimate);
  return {e.position_m.x(),
          e.position_m.y(),
          e.position_m.z(),
          aar_geometry::RadToDeg(e.orientation_rad.roll),
          aar_geometry::RadToDeg(e.orientation_rad.pitch),
          aar_geometry::RadToDeg(e.orientation_rad.yaw)};
}

// A level or limit as FrameRecord keeps it: NaN for none (0 from a publisher without integrity).
double LevelOrNan(double value) {
  return value > 0.0 ? value : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

Evaluator::FrameStatus Evaluator::AddFrame(int64_t stamp_ns, double now_s) {
  if (!frames_.empty() && stamp_ns <= frames_.back().stamp_ns)
    return stamp_ns < frames_.back().stamp_ns ? FrameStatus::kOlder : FrameStatus::kRepeat;
  frames_.push_back({stamp_ns, now_s});
  return FrameStatus::kNew;
}

bool Evaluator::AddEstimate(int64_t stamp_ns, const Estimate& estimate) {
  if (settled_.count(stamp_ns)) return false;
  estimates_[stamp_ns] = estimate;
  return true;
}

bool Evaluator::AddOutcome(int64_t stamp_ns, const StageOutcome& outcome) {
  if (settled_.count(stamp_ns)) return false;
  outcomes_[stamp_ns].push_back(outcome);
  return true;
}

bool Evaluator::Resolved(int64_t stamp_ns) const {
  if (estimates_.count(stamp_ns)) return true;
  // Estimates come on one connection in stamp order: once an announced later frame has its
  // estimate, this frame's will not come (lost, e.g. before eval's subscription was linked).
  // Without this, one lost estimate held every later frame for settle_after.
  const auto later = estimates_.upper_bound(stamp_ns);
  if (later != estimates_.end() && !frames_.empty() && later->first <= frames_.back().stamp_ns)
    return true;
  const auto it = outcomes_.find(stamp_ns);
  if (it == outcomes_.end()) return false;
  for (const StageOutcome& o : it->second)
    if (IsFinal(o)) return true;
  return false;
}

std::vector<SettledFrame> Evaluator::SettleReady(double now_s, const TruthReady& ready,
                                                 const TruthLookup& truth) {
  std::vector<SettledFrame> out;
  while (!frames_.empty()) {
    const Announced& f = frames_.front();
    const bool due = now_s - f.at_s >= settle_after_;
    // Once the simulator measures visibility, a frame waits for its own as for its truth: the
    // message travels on its own connection and may come after the estimate.
    const bool visibility = !visibility_seen_ || visibility_.count(f.stamp_ns);
    if (!due && !(Resolved(f.stamp_ns) && ready(f.stamp_ns) && visibility)) break;
    out.push_back(SettleFront(truth));
  }
  return out;
}

std::vector<SettledFrame> Evaluator::SettleAll(const TruthLookup& truth) {
  std::vector<SettledFrame> out;
  while (!frames_.empty()) out.push_back(SettleFront(truth));
  return out;
}

bool Evaluator::AddVisibility(int64_t stamp_ns, const std::vector<CameraVisibility>& views,
                              size_t rig) {
  if (settled_.count(stamp_ns)) return false;
  auto& rigs = visibility_[stamp_ns];
  if (rigs.size() <= rig) rigs.resize(rig + 1);
  rigs[rig] = views;
  visibility_seen_ = true;
  return true;
}

namespace {

// The view that saw most of the receiver (most visible pixels; of equals, the larger share),
// into the frame's record (0 pixels and a NaN share when none saw it), and the least share of
// any view of a rig (a view without the receiver in it: 0), of the rig where that is most. By
// pixels, not by share: a sliver at the image's edge, wholly visible, is not the better view of a
// receiver another camera sees whole.
void TakeBestView(const std::vector<std::vector<CameraVisibility>>& rigs, FrameRecord& f) {
  f.visible_px = 0.0;
  double best_least = -std::numeric_limits<double>::infinity();
  for (const std::vector<CameraVisibility>& views : rigs) {
    if (views.empty()) continue;  // this rig's did not come
    double least = std::numeric_limits<double>::infinity();
    for (const CameraVisibility& v : views) {
      const double share =
          v.silhouette_px > 0 ? static_cast<double>(v.visible_px) / v.silhouette_px : 0.0;
      least = std::min(least, share);
      if (v.silhouette_px <= 0) continue;
      if (std::isnan(f.visible_fraction) || v.visible_px > f.visible_px ||
          (v.visible_px == f.visible_px && share > f.visible_fraction)) {
        f.visible_fraction = share;
        f.visible_px = v.visible_px;
      }
    }
    best_least = std::max(best_least, least);
  }
  if (!std::isnan(f.visible_fraction)) f.visible_fraction_least = best_least;  // else in no view
}

}  // namespace

SettledFrame Evaluator::SettleFront(const TruthLookup& truth) {
  SettledFrame s;
  s.stamp_ns = frames_.front().stamp_ns;
  frames_.pop_front();
  settled_.insert(s.stamp_ns);
  s.record.t = ToSec(s.stamp_ns) - stamp_offset_;
  std::string error;
  const std::optional<Eigen::Isometry3d> T_truth = truth(s.stamp_ns, &error);
  if (!T_truth) {
    s.no_truth = error.empty() ? "no truth" : error;
    ++no_truth_;
  }
  const auto estimate = estimates_.find(s.stamp_ns);
  const auto reports = outcomes_.find(s.stamp_ns);
  s.ledger = ClassifyFrame(
      estimate != estimates_.end() ? &estimate->second : nullptr,
      reports != outcomes_.end() ? reports->second : std::vector<StageOutcome>{}, s.no_truth);
  s.ledger.stamp_ns = s.stamp_ns;
  s.ledger.t = s.record.t;
  ledger_.push_back(s.ledger);
  const auto visibility = visibility_.find(s.stamp_ns);
  if (visibility != visibility_.end()) TakeBestView(visibility->second, s.record);
  if (T_truth) Score(*T_truth, s);
  if (estimate != estimates_.end()) estimates_.erase(estimate);
  // Reports on this frame and on any older, never announced one are done with.
  outcomes_.erase(outcomes_.begin(), outcomes_.upper_bound(s.stamp_ns));
  visibility_.erase(visibility_.begin(), visibility_.upper_bound(s.stamp_ns));
  return s;
}

void Evaluator::Score(const Eigen::Isometry3d& T_truth, SettledFrame& s) {
  FrameRecord& f = s.record;
  f.range_m = T_truth.translation().norm();
  f.region = aar_geometry::RegionOfRange(f.range_m);
  const auto it = estimates_.find(s.stamp_ns);
  if (it != estimates_.end()) {
    const Estimate& est = it->second;
    if (est.valid) {  // else no pose: a miss
      f.estimated = true;
      f.error = ErrorComponents(T_truth, est.T_tanker_receiver);
      last_estimate_ = est.T_tanker_receiver;
      f.converged = est.converged;
      f.iterations = est.iterations;
      f.rms = est.rms;
      f.registration_ms = est.registration_ms;
      f.nees = Nees(T_truth, est);
      f.pl_position_m = LevelOrNan(est.protection_level_position);
      f.pl_attitude_deg = LevelOrNan(est.protection_level_attitude);
      f.al_position_m = LevelOrNan(est.alert_limit_position);
      f.al_attitude_deg = LevelOrNan(est.alert_limit_attitude);
      position_sum_ += PositionErrorNorm(f);
      ++estimated_;
    }
    f.track = est.track;
    f.alert = est.alert;
  }
  // A live system holds the last estimate through a miss.
  f.published = last_estimate_.has_value();
  if (f.estimated)
    f.published_error = f.error;
  else if (f.published)
    f.published_error = ErrorComponents(T_truth, *last_estimate_);
  records_.push_back(f);
  if (records_.size() % 10 == 1 || !f.estimated) s.progress = ProgressLine(f);
}

std::string Evaluator::ProgressLine(const FrameRecord& f) const {
  std::ostringstream line;
  line << "eval: frame " << records_.size()
       << (expected_frames_ > 0 ? " of " + std::to_string(expected_frames_) : "") << ", "
       << std::fixed << std::setprecision(1) << f.range_m << " m (region "
       << aar_geometry::RegionName(f.region) << "): " << std::setprecision(3);
  if (f.estimated)
    line << "error " << PositionErrorNorm(f) << " m";
  else
    line << "MISSED";
  if (estimated_ > 0)
    line << "; running mean " << position_sum_ / estimated_ << " m over " << estimated_
         << " estimates";
  return line.str();
}

}  // namespace aar_eval
