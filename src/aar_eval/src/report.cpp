#include "aar_eval/report.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "aar_eval/integrity.h"
#include "aar_eval/tables.h"
#include "integrity_section.h"
#include "markdown.h"
#include "run_record.h"
#include "visibility_section.h"

namespace aar_eval {

namespace {

// The experiments' frames, in the report's order, and their region statistics.
struct Experiments {
  std::map<std::string, std::vector<FrameRecord>> records;
  std::vector<std::string> done;  // with results, the baseline first
  std::string baseline;           // "" when there is none or it has no results
  std::map<std::string, std::map<std::string, RegionStats>> stats;  // [experiment][region]
  bool any_miss = false;  // a frame without an estimate of its own
};

// DIR/<experiment>/frames.csv of each experiment that has one; the others into result.missing.
Experiments ReadExperiments(const ReportOptions& options, ReportResult& result) {
  Experiments x;
  for (const auto& e : options.experiments) {
    const std::string csv = options.dir + "/" + e + "/frames.csv";
    if (!std::filesystem::exists(csv)) {
      result.missing.push_back(e);
      continue;
    }
    x.records[e] = ReadFrameCsv(csv);
    x.done.push_back(e);
  }
  if (x.done.empty()) throw std::runtime_error("no experiment has results in " + options.dir);
  if (!options.baseline.empty() && x.records.count(options.baseline)) {
    // the baseline's rows come first, the % differences against it after
    x.baseline = options.baseline;
    x.done.erase(std::find(x.done.begin(), x.done.end(), x.baseline));
    x.done.insert(x.done.begin(), x.baseline);
  }
  for (const auto& e : x.done) {
    x.stats[e] = ComputeRegionStats(x.records[e]);
    if (x.stats[e].count("all") && x.stats[e].at("all").estimated < x.stats[e].at("all").frames)
      x.any_miss = true;
  }
  return x;
}

void WriteIntroduction(std::ostream& out, const std::string& dir) {
  out << "# AAR pose estimation report\n\n";
  WriteRunSection(out, dir);
  out << "Errors are estimate minus truth in the true receiver body frame (x, y, z in metres) and "
         "roll, pitch, yaw of R_truth^T R_estimate (degrees). An experiment's rows average over "
         "the frames it estimated; \"frames (estimated)\" counts both. Each % difference row "
         "compares the experiment with the baseline on the same frames, those both estimated, "
         "and counts them: (baseline - value) / baseline x 100, positive is better.\n\n";
}

// An experiment's coverage row: its region statistics.
struct CoverageRow {
  std::string experiment;
  const std::map<std::string, RegionStats>* stats;
};

// What the region tables leave out, against the plan: frames outside the regions (in no
// table), and a run that flew fewer frames than planned (its tables cover only those).
void WriteCoverageNotes(std::ostream& out, const std::string& dir, Experiments& x) {
  std::vector<std::string> notes;
  for (const auto& e : x.done) {
    const auto& records = x.records[e];
    const std::string note = OutsideRegionsNote(e, {&records});
    if (!note.empty()) notes.push_back(note);
    const std::string short_of_plan = ShortOfPlan(ReadPlannedRun(dir + "/" + e), records.size());
    if (!short_of_plan.empty()) {
      notes.push_back("**" + e + ": " + short_of_plan +
                      "** (why: the Run section); its tables cover only those");
    }
  }
  for (const auto& note : notes) out << "- " << note << "\n";
  if (!notes.empty()) out << "\n";
}

// Estimated of all frames per region, and the miss policy if an experiment missed frames.
void WriteCoverage(std::ostream& out, const std::string& dir, Experiments& x) {
  out << "## Coverage\n\nFrames with an estimate of this frame, of all frames, per region.\n\n";
  Columns<CoverageRow> columns = {
      {"experiment", Align::kLeft, [](const CoverageRow& r) { return r.experiment; }}};
  for (const auto& region : RegionTitles()) {
    const std::string key = region.first;
    columns.push_back({RegionColumnHeader(key), Align::kRight, [key](const CoverageRow& r) {
                         const auto it = r.stats->find(key);
                         if (it == r.stats->end()) return std::string("-");
                         return std::to_string(it->second.estimated) + " / " +
                                std::to_string(it->second.frames);
                       }});
  }
  WriteTableHead(out, columns);
  for (const auto& e : x.done) WriteTableRow(out, columns, CoverageRow{e, &x.stats[e]});
  out << "\n";
  WriteCoverageNotes(out, dir, x);
  if (x.any_miss) {
    out << "Miss policy: a frame without an estimate of its own is a miss. It is in no average "
           "of the tables below; the section \"As published\" scores instead what a live "
           "system publishes, the last estimate held through each miss.\n\n";
  }
}

// Experiment e's headline line after "- e: average improvement over BASELINE: ".
std::string HeadlineImprovement(Experiments& x, const std::string& e) {
  const std::string& baseline = x.baseline;
  const auto paired = ComputePairedRegionStats(x.records[e], x.records[baseline]);
  const auto& mine = paired.value;
  if (!mine.count("all") || mine.at("all").estimated == 0) return "no frame both estimated";
  const int n = mine.at("all").estimated;
  const int frames = x.stats[e].count("all") ? x.stats[e].at("all").frames : 0;
  std::ostringstream s;
  s << Fixed(AverageImprovement(mine.at("all"), paired.baseline.at("all")), 1) << "%";
  const int e_estimated = x.stats[e].at("all").estimated;
  const int b_estimated =
      x.stats[baseline].count("all") ? x.stats[baseline].at("all").estimated : 0;
  if (n == frames && e_estimated == frames && b_estimated == frames)
    s << " on every frame (" << n << ")";
  else
    s << " on the " << n << " frames both estimated (" << e << " estimated " << e_estimated
      << " of " << frames << ", " << baseline << " " << b_estimated << ")";
  if (e == "dynamic") s << " (thesis: 74.1%, on every frame)";
  if (n != frames) {
    const auto held =
        ComputePairedRegionStats(x.records[e], x.records[baseline], ErrorPolicy::kHoldLast);
    const auto& hm = held.value;
    if (hm.count("all") && hm.at("all").estimated > 0) {
      s << "; as published (the last estimate held through misses): "
        << Fixed(AverageImprovement(hm.at("all"), held.baseline.at("all")), 1) << "% on "
        << hm.at("all").estimated << " frames";
    }
  }
  return s.str();
}

// The thesis's statistic for each experiment against the baseline.
void WriteHeadline(std::ostream& out, Experiments& x) {
  out << "## Headline\n\nThe thesis's statistic: the mean over the six components, whole "
         "approach, of the % difference of the average error magnitude against "
      << x.baseline << ", on the frames both estimated.\n\n";
  for (const auto& e : x.done) {
    if (e == x.baseline) continue;
    out << "- " << e << ": average improvement over " << x.baseline << ": "
        << HeadlineImprovement(x, e) << "\n";
  }
  out << "\n";
}

// Average error magnitude and RMS error per region, and with misses what is published.
void WriteErrorTables(std::ostream& out, const Experiments& x) {
  out << "## Average error magnitude\n\n"
      << MarkdownRegionTable(x.records, x.done, x.baseline, false);
  out << "\n## RMS error\n\n" << MarkdownRegionTable(x.records, x.done, x.baseline, true);
  if (x.any_miss) {
    out << "\n## As published: the last estimate held through misses\n\nAverage error "
           "magnitude of what a live system publishes on each frame: its estimate, or on a miss "
           "the last estimate again, against this frame's truth. Frames before the first "
           "estimate have nothing published and are left out; \"frames (published)\" counts "
           "both.\n\n"
        << MarkdownRegionTable(x.records, x.done, x.baseline, false, ErrorPolicy::kHoldLast);
  }
  out << "\nWhat these numbers mean for the default approach, and why: docs/RESULTS.md.\n";
}

// DIR/plots/<experiment>_{position,orientation}.png where they exist.
void WritePlots(std::ostream& out, const std::string& dir, const std::vector<std::string>& done) {
  out << "\n## Error against range\n\n";
  for (const auto& e : done) {
    for (const char* kind : {"position", "orientation"}) {
      const std::string png = "plots/" + e + "_" + kind + ".png";
      if (std::filesystem::exists(dir + "/" + png))
        out << "![" << e << " " << kind << "](" << png << ")\n\n";
    }
  }
}

// Headless rviz captures (scripts/capture), if the run made them.
void WriteCaptures(std::ostream& out, const std::string& dir) {
  std::vector<std::string> captures;
  if (std::filesystem::is_directory(dir + "/captures")) {
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/captures")) {
      if (entry.path().extension() == ".png") captures.push_back(entry.path().filename());
    }
  }
  std::sort(captures.begin(), captures.end());
  if (captures.empty()) return;
  out << "## rviz captures\n\n"
      << "config/rviz/aar.rviz on rosbags/sample_contact.bag (experiment flight, near "
         "contact): sensed cloud without the boom white, removed boom points magenta, dynamic "
         "reference by "
         "class (both cameras red, left only cyan, right only blue, neither green), shadow "
         "volumes translucent (left blue, right orange), receiver at the estimate orange.\n\n";
  for (const auto& png : captures) out << "![" << png << "](captures/" << png << ")\n\n";
}

}  // namespace

ReportResult WriteReport(const ReportOptions& options) {
  ReportResult result;
  result.path = options.dir + "/report.md";
  Experiments x = ReadExperiments(options, result);

  std::ofstream out(result.path);
  WriteIntroduction(out, options.dir);
  WriteCoverage(out, options.dir, x);
  std::vector<ExperimentRuns> runs;
  for (const auto& e : x.done) runs.push_back({e, {&x.records[e]}});
  const std::string visibility = VisibilitySection(runs);
  if (!visibility.empty()) out << visibility << "\n";
  if (!x.baseline.empty()) WriteHeadline(out, x);
  WriteErrorTables(out, x);
  const IntegrityOptions integrity{options.protection_level_scale};
  std::map<std::string, std::map<std::string, IntegrityStats>> integrity_stats;
  for (const auto& e : x.done) integrity_stats[e] = ComputeIntegrityStats(x.records[e], integrity);
  WriteIntegritySection(out, x.done, integrity_stats, integrity, options.dir);
  WritePlots(out, options.dir, x.done);
  WriteCaptures(out, options.dir);
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw std::runtime_error(result.path + ": write failed");
  result.experiments = x.done;
  return result;
}

}  // namespace aar_eval
