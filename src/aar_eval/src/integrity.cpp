#include "aar_eval/integrity.h"

#include <cmath>
#include <limits>

#include <aar_geometry/pose.h>

namespace aar_eval {

namespace {

double Nan() { return std::numeric_limits<double>::quiet_NaN(); }

}  // namespace

double AttitudeErrorAngleDeg(const FrameRecord& f) {
  const Eigen::Matrix3d R = aar_geometry::RotationFromRollPitchYaw(
      {aar_geometry::DegToRad(f.error[3]), aar_geometry::DegToRad(f.error[4]),
       aar_geometry::DegToRad(f.error[5])});
  return aar_geometry::RadToDeg(Eigen::AngleAxisd(R).angle());
}

FrameIntegrity ClassifyIntegrity(const FrameRecord& f, const IntegrityOptions& options) {
  FrameIntegrity out;
  const double pl_position = f.pl_position_m * options.protection_level_scale;
  const double pl_attitude = f.pl_attitude_deg * options.protection_level_scale;
  // Scaled levels: the alert follows them (IntegrityOptions::protection_level_scale).
  bool alert = f.alert;
  const bool own_beyond =
      f.pl_position_m > f.al_position_m || f.pl_attitude_deg > f.al_attitude_deg;
  if (options.protection_level_scale != 1.0 && (!alert || own_beyond))
    alert = pl_position > f.al_position_m || pl_attitude > f.al_attitude_deg;
  if (!f.estimated || alert || std::isnan(pl_position) || std::isnan(pl_attitude)) return out;
  const double position = PositionErrorNorm(f);
  const double attitude = AttitudeErrorAngleDeg(f);
  out.misleading = position > pl_position || attitude > pl_attitude;
  // A NaN limit compares false: without limits a frame is not available.
  out.available = pl_position <= f.al_position_m && pl_attitude <= f.al_attitude_deg;
  out.hazardous = out.available && (position > f.al_position_m || attitude > f.al_attitude_deg);
  return out;
}

double IntegrityStats::NeesMean() const { return with_nees ? nees_sum / with_nees : Nan(); }

double IntegrityStats::BeyondNeesBoundShare() const {
  return with_nees ? static_cast<double>(beyond_nees_bound) / with_nees : Nan();
}

double IntegrityStats::Availability() const {
  return frames ? static_cast<double>(available) / frames : Nan();
}

IntegrityStats& IntegrityStats::operator+=(const IntegrityStats& o) {
  frames += o.frames;
  estimated += o.estimated;
  with_levels += o.with_levels;
  alert += o.alert;
  with_nees += o.with_nees;
  nees_sum += o.nees_sum;
  beyond_nees_bound += o.beyond_nees_bound;
  misleading += o.misleading;
  hazardous += o.hazardous;
  available += o.available;
  return *this;
}

std::map<std::string, IntegrityStats> ComputeIntegrityStats(const std::vector<FrameRecord>& frames,
                                                            const IntegrityOptions& options) {
  std::map<std::string, IntegrityStats> stats;
  for (const auto& f : frames) {
    if (f.region == aar_geometry::Region::kOutside) continue;
    IntegrityStats one;
    one.frames = 1;
    if (f.estimated) {
      one.estimated = 1;
      one.with_levels = !std::isnan(f.pl_position_m) && !std::isnan(f.pl_attitude_deg);
      one.alert = f.alert;
      if (std::isfinite(f.nees)) {
        one.with_nees = 1;
        one.nees_sum = f.nees;
        one.beyond_nees_bound = f.nees > kNees999Bound6Dof;
      }
      const FrameIntegrity c = ClassifyIntegrity(f, options);
      one.misleading = c.misleading;
      one.hazardous = c.hazardous;
      one.available = c.available;
    }
    stats[aar_geometry::RegionName(f.region)] += one;
    stats["all"] += one;
  }
  return stats;
}

}  // namespace aar_eval
