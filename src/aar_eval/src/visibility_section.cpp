#include "visibility_section.h"

#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "markdown.h"

namespace aar_eval {
namespace {

// The bins of visible fraction, and one for frames whose receiver was in no view.
constexpr std::array<double, 5> kBinStarts = {0.0, 0.25, 0.5, 0.75, 0.9};
constexpr size_t kNotInView = kBinStarts.size();
constexpr size_t kColumns = kBinStarts.size() + 1;

// Frames and frames estimated per bin, of one experiment in one region.
struct BinCounts {
  std::string experiment, region;
  std::array<int, kColumns> frames{}, estimated{};
};

// Which of a frame's shares a table bins by.
using Share = double FrameRecord::*;

// The bin of a measured frame's `share`.
size_t BinOf(double share) {
  if (std::isnan(share)) return kNotInView;
  size_t bin = 0;
  while (bin + 1 < kBinStarts.size() && share >= kBinStarts[bin + 1]) ++bin;
  return bin;
}

// Counts the measured frames of the runs in region `key` ("all": every region) by `share`;
// false when none was measured.
bool Count(const std::vector<const std::vector<FrameRecord>*>& runs, const std::string& key,
           Share share, BinCounts& counts) {
  bool measured = false;
  for (const std::vector<FrameRecord>* run : runs) {
    for (const FrameRecord& f : *run) {
      if (std::isnan(f.visible_px)) continue;                                 // not measured
      if (std::isnan(f.*share) && !std::isnan(f.visible_fraction)) continue;  // this share not
      if (f.region == aar_geometry::Region::kOutside) continue;
      if (key != "all" && aar_geometry::RegionName(f.region) != key) continue;
      measured = true;
      const size_t bin = BinOf(f.*share);
      ++counts.frames[bin];
      counts.estimated[bin] += f.estimated ? 1 : 0;
    }
  }
  return measured;
}

// Whether any frame has the least view's share (files before it have none).
bool AnyLeast(const std::vector<ExperimentRuns>& experiments) {
  for (const auto& [experiment, runs] : experiments)
    for (const std::vector<FrameRecord>* run : runs)
      for (const FrameRecord& f : *run)
        if (!std::isnan(f.visible_fraction_least)) return true;
  return false;
}

std::string BinHeader(size_t bin) {
  if (bin == kNotInView) return "in no view";
  const auto percent = [](double x) { return std::to_string(std::lround(x * 100.0)); };
  if (bin + 1 == kBinStarts.size()) return ">= " + percent(kBinStarts[bin]) + " %";
  return percent(kBinStarts[bin]) + "-" + percent(kBinStarts[bin + 1]) + " %";
}

Columns<BinCounts> VisibilityColumns() {
  Columns<BinCounts> columns = {
      {"experiment", Align::kLeft, [](const BinCounts& c) { return c.experiment; }},
      {"region", Align::kLeft, [](const BinCounts& c) { return c.region; }}};
  for (size_t bin = 0; bin < kColumns; ++bin) {
    columns.push_back({BinHeader(bin), Align::kRight, [bin](const BinCounts& c) {
                         if (c.frames[bin] == 0) return std::string("-");
                         return std::to_string(c.estimated[bin]) + " / " +
                                std::to_string(c.frames[bin]);
                       }});
  }
  return columns;
}

}  // namespace

std::string VisibilitySection(const std::vector<ExperimentRuns>& experiments) {
  const auto rows = [&](Share share) {
    std::vector<BinCounts> out;
    for (const auto& [experiment, runs] : experiments) {
      for (const auto& [key, title] : RegionTitles()) {
        BinCounts counts{experiment, key, {}, {}};
        if (Count(runs, key, share, counts)) out.push_back(counts);
      }
    }
    return out;
  };
  const std::vector<BinCounts> best = rows(&FrameRecord::visible_fraction);
  if (best.empty()) return "";
  std::ostringstream out;
  out << "## Coverage against visibility\n\nFrames with an estimate of their own, of all "
         "frames, by the share of the receiver's silhouette that the boom left visible (the "
         "simulator's measure: the receiver drawn alone against the frame's labels), in the "
         "camera that saw most of it. A miss where little is visible is the sensor's; one where "
         "much is visible is the estimator's.\n\n";
  const Columns<BinCounts> columns = VisibilityColumns();
  WriteTableHead(out, columns);
  for (const BinCounts& row : best) WriteTableRow(out, columns, row);
  if (!AnyLeast(experiments)) return out.str();  // files from before the least view was written
  const std::vector<BinCounts> least = rows(&FrameRecord::visible_fraction_least);
  out << "\nThe same by the camera that saw least of it: stereo needs the receiver in both "
         "views, and flight's start from the images searches the left one (flight_both_views: "
         "both). The cameras are 0.5 m apart, the boom a few metres away: one may see a far "
         "receiver whole while the boom hides it from the other.\n\n";
  WriteTableHead(out, columns);
  for (const BinCounts& row : least) WriteTableRow(out, columns, row);
  return out.str();
}

}  // namespace aar_eval
