#pragma once

#include <array>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <aar_geometry/pose_error.h>

namespace aar_eval {

// One frame of one experiment: the truth's range and region, and the error if there was an
// estimate (a frame without one is a miss).
struct FrameRecord {
  double t = 0.0;        // [s] path time
  double range_m = 0.0;  // [m] truth
  aar_geometry::Region region = aar_geometry::Region::kOutside;
  bool estimated = false;
  // Position error along the true body axes [m], then roll, pitch, yaw error [deg].
  std::array<double, 6> error{};
  bool converged = false;
  int iterations = 0;
  double rms = 0.0;              // [m] ICP
  double registration_ms = 0.0;  // [ms]
  std::string track = "off";     // the tracker's outcome (aar_msgs/PoseEstimate TRACK_*), by name
  // Normalised estimation error squared of the pose against its covariance (6 degrees of
  // freedom: about 6 on average when the covariance is honest); NaN without a covariance.
  double nees = std::numeric_limits<double>::quiet_NaN();
  // The miss policy of a live system: on a miss it holds (publishes again) the last estimate.
  // `published`: this frame's estimate or a held one exists (false only before the first
  // estimate); `published_error` is its error against this frame's truth, as `error`.
  bool published = false;
  std::array<double, 6> published_error{};
  // Integrity, the estimate's own (aar_msgs/PoseEstimate): its protection levels, a bound on the
  // position error's norm [m] and one on the attitude error's rotation angle [deg], and the alert
  // limits of its phase; NaN when the frame was not estimated or its estimate has none.
  double pl_position_m = std::numeric_limits<double>::quiet_NaN();
  double pl_attitude_deg = std::numeric_limits<double>::quiet_NaN();
  double al_position_m = std::numeric_limits<double>::quiet_NaN();
  double al_attitude_deg = std::numeric_limits<double>::quiet_NaN();
  // The frame's estimate was published in alert (not to be used); false when no estimate came.
  bool alert = false;
  // What the boom left of the receiver in the camera that saw most of it (most visible pixels;
  // the simulator's aar_msgs/Visibility): the fraction of its silhouette in view that was
  // visible, and those pixels. Both NaN when not measured (a bag, a real rig); a receiver in no
  // view has 0 pixels and a NaN fraction.
  double visible_fraction = std::numeric_limits<double>::quiet_NaN();
  double visible_px = std::numeric_limits<double>::quiet_NaN();
  // The same share in the camera that saw least of it (a camera without the receiver in view,
  // while another has it: 0): stereo needs both views. With more rigs, that of the rig whose
  // weaker camera saw most. NaN as above.
  double visible_fraction_least = std::numeric_limits<double>::quiet_NaN();
};

// |x, y, z| of a frame's own position error [m].
double PositionErrorNorm(const FrameRecord& frame);

// Which error a table is over: each frame's own estimate (misses left out), or what a live
// system publishes under "hold the last estimate" (only frames before the first estimate left
// out).
enum class ErrorPolicy { kEstimated, kHoldLast };

// Per region and component: average error magnitude and RMS error (thesis Eq. 7), over the frames
// that have an estimate (or, under ErrorPolicy::kHoldLast, a published pose).
struct RegionStats {
  int frames = 0;     // all frames in the region
  int estimated = 0;  // frames in the averages: with an estimate (or a published pose)
  std::array<double, 6> mean_abs{};
  std::array<double, 6> rms{};
};

// The component names in table order, with units: "x (m)", ..., "yaw (deg)".
const std::array<std::string, 6>& ComponentNames();

// The keys of ComputeRegionStats in table order ("A", "B", "C", "all") with their titles
// ("Region A (175-70 m)", ..., "Whole approach").
const std::vector<std::pair<std::string, std::string>>& RegionTitles();

// Region A, B, C and the whole approach ("all": every frame in A, B or C).
std::map<std::string, RegionStats> ComputeRegionStats(const std::vector<FrameRecord>& frames,
                                                      ErrorPolicy policy = ErrorPolicy::kEstimated);

// The frames of `a` and `b` (matched by path time to 1 ms) that both have an error under
// `policy`, in `a`'s order: the only fair ground for a % difference between two experiments.
std::pair<std::vector<FrameRecord>, std::vector<FrameRecord>> CommonFrames(
    const std::vector<FrameRecord>& a, const std::vector<FrameRecord>& b,
    ErrorPolicy policy = ErrorPolicy::kEstimated);

// The region stats of `a` and of `b` on their common frames (CommonFrames) under `policy`: what
// every % comparison of two experiments is computed from.
struct PairedRegionStats {
  std::map<std::string, RegionStats> value;     // `a`'s
  std::map<std::string, RegionStats> baseline;  // `b`'s, on the same frames
};
PairedRegionStats ComputePairedRegionStats(const std::vector<FrameRecord>& a,
                                           const std::vector<FrameRecord>& b,
                                           ErrorPolicy policy = ErrorPolicy::kEstimated);

// A confidently wrong track: the longest run of consecutive frames in regions B and C whose own
// estimate is more than `max_position_m` (the position error's norm) or `max_angle_deg` (the
// largest of roll, pitch and yaw) off. A frame without an estimate (a lost track says so) ends a
// run. Its length is from its first frame's time to that of the first frame after it (the last
// frame's spacing at the end of the path); 0 when there is none.
struct WrongLock {
  double seconds = 0.0;
  double start_t = 0.0;  // [s] path time of its first frame
  int frames = 0;
};
WrongLock LongestWrongLock(const std::vector<FrameRecord>& frames, double max_position_m = 0.5,
                           double max_angle_deg = 2.0);

// The thesis's % difference of `value` against `baseline`: (baseline - value) / baseline * 100,
// positive when `value` is smaller (better). NaN when the baseline is 0.
double PercentDifference(double value, double baseline);

// CSV of records (header t,range_m,region,estimated,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,
// converged,iterations,rms_m,registration_ms,track,nees,published,published_x_m, ...,
// published_yaw_deg,pl_position_m,pl_attitude_deg,al_position_m,al_attitude_deg,alert). Read
// also takes the shorter headers of earlier runs (without the published columns, published
// means estimated; without the integrity ones, a frame has no levels and no alert). Throws
// aar_geometry::LoadError naming file and line.
void WriteFrameCsv(const std::string& path, const std::vector<FrameRecord>& frames);
std::vector<FrameRecord> ReadFrameCsv(const std::string& path);
std::string FrameCsvHeader();
std::string FrameCsvRow(const FrameRecord& frame);

// Markdown table in the thesis's layout: for each region, one row per experiment of average
// error magnitude (and RMS with `rms` set) over its frames with an error under `policy`, plus a
// "% difference" row for each experiment against `baseline` (an experiment name; empty: none).
// A % row compares the two on the same frames, those both have an error on, and counts them.
std::string MarkdownRegionTable(
    const std::map<std::string, std::vector<FrameRecord>>& by_experiment,
    const std::vector<std::string>& experiment_order, const std::string& baseline, bool rms,
    ErrorPolicy policy = ErrorPolicy::kEstimated);

// The thesis's headline: the mean over the six components, whole approach, of the % difference
// of the average error magnitude against the baseline.
double AverageImprovement(const RegionStats& value, const RegionStats& baseline);

}  // namespace aar_eval
