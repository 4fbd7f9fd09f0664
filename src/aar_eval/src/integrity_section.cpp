#include "integrity_section.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "markdown.h"

namespace aar_eval {
namespace {

// One row: an experiment's figures in one region.
struct IntegrityRow {
  std::string experiment;
  std::string region;  // a key of RegionTitles()
  const IntegrityStats* s;
};

// `value` at `digits` decimals; "-" when it is NaN.
std::string FixedOrDash(double value, int digits) {
  return std::isnan(value) ? "-" : Fixed(value, digits);
}

// A count judged against the protection levels; "-" when no estimate had levels.
std::string LevelCount(const IntegrityStats& s, int count) {
  return s.with_levels ? std::to_string(count) : "-";
}

const Columns<IntegrityRow>& IntegrityColumns() {
  static const Columns<IntegrityRow> columns = {
      {"experiment", Align::kLeft, [](const IntegrityRow& r) { return r.experiment; }},
      {"region", Align::kLeft, [](const IntegrityRow& r) { return RegionColumnHeader(r.region); }},
      {"estimated / frames", Align::kRight,
       [](const IntegrityRow& r) {
         return std::to_string(r.s->estimated) + " / " + std::to_string(r.s->frames);
       }},
      {"NEES mean", Align::kRight,
       [](const IntegrityRow& r) { return FixedOrDash(r.s->NeesMean(), 2); }},
      {"beyond 99.9 % (%)", Align::kRight,
       [](const IntegrityRow& r) { return FixedOrDash(100.0 * r.s->BeyondNeesBoundShare(), 1); }},
      {"misleading", Align::kRight,
       [](const IntegrityRow& r) { return LevelCount(*r.s, r.s->misleading); }},
      {"HMI", Align::kRight,
       [](const IntegrityRow& r) { return LevelCount(*r.s, r.s->hazardous); }},
      {"availability (%)", Align::kRight, [](const IntegrityRow& r) {
         return r.s->with_levels ? FixedOrDash(100.0 * r.s->Availability(), 1) : "-";
       }}};
  return columns;
}

}  // namespace

void WriteIntegritySection(
    std::ostream& out, const std::vector<std::string>& order,
    const std::map<std::string, std::map<std::string, IntegrityStats>>& stats,
    const IntegrityOptions& options, const std::string& dir, const std::string& summed) {
  out << "\n## Integrity\n\n"
      << "Per experiment and region: the frames estimated of all frames; the NEES mean over the "
         "frames with a NEES (6 degrees of freedom: about 6 when the covariance is honest); "
         "beyond 99.9 %: the share of those whose NEES exceeds "
      << Fixed(kNees999Bound6Dof, 3)
      << ", the chi-square 99.9 % point for 6 degrees of freedom (0.1 % when honest); "
         "misleading: frames estimated and not in alert whose position error (the norm of x, y, "
         "z) or attitude error (the rotation angle of the roll, pitch, yaw error) exceeds its "
         "protection level; HMI (hazardously misleading): available frames whose position or "
         "attitude error exceeds its alert limit; availability: the share of all the region's "
         "frames that are available, estimated, not in alert and with both protection levels "
         "within their alert limits (a miss is unavailable). The protection levels and alert "
         "limits are the estimates' own (frames.csv), each level stated by its publisher at the "
         "integrity risk per frame it gives (aar_msgs/PoseEstimate integrity_risk). \"-\": no "
         "frame with a NEES, or no estimate with protection levels (a publisher without "
         "integrity).";
  if (!summed.empty()) out << " " << summed;
  out << "\n\n";
  if (options.protection_level_scale != 1.0) {
    std::ostringstream scale;
    scale << options.protection_level_scale;
    out << "**Protection levels scaled by " << scale.str()
        << "** (make_report --protection-level-scale): misleading, HMI and availability are "
           "not the estimates' own; above 1 they are those of an overbound factor that much "
           "larger, below 1 a check.\n\n";
  }
  const Columns<IntegrityRow>& columns = IntegrityColumns();
  WriteTableHead(out, columns);
  for (const auto& e : order) {
    const auto by_region = stats.find(e);
    if (by_region == stats.end()) continue;
    for (const auto& [key, title] : RegionTitles()) {
      const auto it = by_region->second.find(key);
      if (it != by_region->second.end()) WriteTableRow(out, columns, {e, key, &it->second});
    }
  }
  bool heading = false;
  for (const auto& e : order) {
    const std::string png = "plots/" + e + "_stanford.png";
    if (!stats.count(e) || !std::filesystem::exists(dir + "/" + png)) continue;
    if (!heading)
      out << "\nStanford diagrams: error against protection level per region, the alert limit "
             "as lines, frames in alert marked apart.\n";
    heading = true;
    out << "\n![" << e << " Stanford diagram](" << png << ")\n";
  }
}

}  // namespace aar_eval
