#pragma once

#include <map>
#include <string>
#include <vector>

#include "aar_eval/tables.h"

namespace aar_eval {

// The chi-square distribution's 99.9 % point for 6 degrees of freedom: a consistent 6-DoF
// covariance puts 0.1 % of the frames' NEES beyond it.
constexpr double kNees999Bound6Dof = 22.458;

// The rotation angle [deg, 0 to 180] of the frame's own attitude error, the rotation of its roll,
// pitch and yaw error (intrinsic z-y'-x'').
double AttitudeErrorAngleDeg(const FrameRecord& frame);

struct IntegrityOptions {
  // The protection levels are multiplied by it before they are compared (with the errors and the
  // alert limits), and the alert follows them as their publisher raises it: a frame whose scaled
  // levels exceed its limits is in alert; a frame in alert whose own levels exceeded its limits
  // is taken as alerted for that alone, so its alert follows the scaled levels. Above 1 (and with
  // no level bias) that is exactly what a publisher whose overbound factor is that much larger
  // gives, the estimates being the same: the levels feed nothing back. Below 1 it shows what
  // levels that much smaller would have let through (a frame in alert for its levels and for
  // another reason is then counted as not alerted). 1 for the published figures.
  double protection_level_scale = 1.0;
};

// How a frame's estimate stands against its protection levels and alert limits. Only a frame
// estimated and not in alert can be any of these, and only with both levels (a level of NaN:
// none).
struct FrameIntegrity {
  // Misleading: the position error's norm or the attitude error's angle beyond its level.
  bool misleading = false;
  // Available: both levels within their alert limits: the pose could be used.
  bool available = false;
  // Hazardously misleading: available, and the position or the attitude error beyond its alert
  // limit (and so beyond its level: a misleading frame too).
  bool hazardous = false;
};
FrameIntegrity ClassifyIntegrity(const FrameRecord& frame, const IntegrityOptions& options = {});

// A region's integrity figures: counts, so that they add up over runs (operator+=).
struct IntegrityStats {
  int frames = 0;             // all frames in the region
  int estimated = 0;          // with an estimate of their own
  int with_levels = 0;        // estimated, with both protection levels
  int alert = 0;              // estimated, in alert
  int with_nees = 0;          // estimated, with a finite NEES
  double nees_sum = 0.0;      // of those
  int beyond_nees_bound = 0;  // of those, beyond kNees999Bound6Dof
  int misleading = 0;
  int hazardous = 0;  // hazardously misleading
  int available = 0;

  double NeesMean() const;              // NaN without a NEES
  double BeyondNeesBoundShare() const;  // of the frames with a NEES, [0, 1]; NaN without one
  double Availability() const;  // available of all frames (a miss is unavailable); NaN: none
  IntegrityStats& operator+=(const IntegrityStats& other);
};

// Region A, B, C and the whole approach ("all": every frame in A, B or C), the keys of
// RegionTitles(); a region without frames has no entry.
std::map<std::string, IntegrityStats> ComputeIntegrityStats(const std::vector<FrameRecord>& frames,
                                                            const IntegrityOptions& options = {});

}  // namespace aar_eval
