#include "aar_eval/report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <stdexcept>

#include "aar_eval/tables.h"

namespace aar_eval {

ReportResult WriteReport(const ReportOptions& options) {
  const std::string& dir = options.dir;
  const std::string& baseline = options.baseline;
  ReportResult result;
  result.path = dir + "/report.md";
  std::map<std::string, std::map<std::string, RegionStats>> stats;
  std::map<std::string, std::vector<FrameRecord>> records;
  std::vector<std::string> done;
  for (const auto& e : options.experiments) {
    const std::string csv = dir + "/" + e + "/frames.csv";
    if (!std::filesystem::exists(csv)) {
      result.missing.push_back(e);
      continue;
    }
    records[e] = ReadFrameCsv(csv);
    stats[e] = ComputeRegionStats(records[e]);
    done.push_back(e);
  }
  if (done.empty()) throw std::runtime_error("no experiment has results in " + dir);
  const bool has_baseline = !baseline.empty() && stats.count(baseline);
  if (has_baseline) {  // the baseline's rows come first, the % differences against it after
    done.erase(std::find(done.begin(), done.end(), baseline));
    done.insert(done.begin(), baseline);
  }

  std::ofstream out(result.path);
  out << "# AAR pose estimation report\n\n";
  std::ifstream run(dir + "/run.txt");
  if (run && run.peek() != std::ifstream::traits_type::eof())
    out << "## Run\n\n```\n" << run.rdbuf() << "```\n\n";
  out << "Errors are estimate minus truth in the true receiver body frame (x, y, z in metres) "
         "and "
         "roll, pitch, yaw of R_truth^T R_estimate (degrees). Averages and RMS are over the "
         "frames "
         "with an estimate; \"frames (estimated)\" counts both. % difference = (baseline - "
         "value) / "
         "baseline x 100: positive is better.\n\n";
  if (has_baseline) {
    out << "## Headline\n\n";
    for (const auto& e : done) {
      if (e == baseline || !stats[e].count("all") || !stats[baseline].count("all")) continue;
      const RegionStats& a = stats[e].at("all");
      const RegionStats& b = stats[baseline].at("all");
      out << "- " << e << ": average improvement over " << baseline << ": " << std::fixed
          << std::setprecision(1) << AverageImprovement(a, b) << "%"
          << (e == "dynamic" ? " (thesis: 74.1%)" : "");
      // Frames by index at 1 ms: path times come from a CSV.
      auto key = [](double t) { return std::llround(t * 1000.0); };
      std::map<long long, const FrameRecord*> theirs;
      for (const auto& f : records[baseline]) {
        if (f.estimated) theirs[key(f.t)] = &f;
      }
      std::vector<FrameRecord> mine_common, theirs_common;
      for (const auto& f : records[e]) {
        const auto it = theirs.find(key(f.t));
        if (!f.estimated || it == theirs.end()) continue;
        mine_common.push_back(f);
        theirs_common.push_back(*it->second);
      }
      const bool same_frames = mine_common.size() == static_cast<size_t>(a.estimated) &&
                               mine_common.size() == static_cast<size_t>(b.estimated);
      if (!same_frames) {  // averages over different frames: say so, and compare the common ones
        out << "; over different frames: " << e << " estimated " << a.estimated << " of "
            << a.frames << ", " << baseline << " " << b.estimated << " of " << b.frames
            << " (the rest are misses, in no average)";
        const auto m = ComputeRegionStats(mine_common);
        const auto t = ComputeRegionStats(theirs_common);
        if (m.count("all") && t.count("all")) {
          out << "; on the " << mine_common.size()
              << " frames both estimated: " << AverageImprovement(m.at("all"), t.at("all")) << "%";
        }
      }
      out << "\n";
    }
    out << "\n";
  }
  out << "## Average error magnitude\n\n"
      << MarkdownRegionTable(stats, done, has_baseline ? baseline : "", false);
  out << "\n## RMS error\n\n"
      << MarkdownRegionTable(stats, done, has_baseline ? baseline : "", true);
  out << "\nWhat these numbers mean for the default approach, and why: docs/RESULTS.md.\n";
  out << "\n## Error against range\n\n";
  for (const auto& e : done) {
    for (const char* kind : {"position", "orientation"}) {
      const std::string png = "plots/" + e + "_" + kind + ".png";
      if (std::filesystem::exists(dir + "/" + png))
        out << "![" << e << " " << kind << "](" << png << ")\n\n";
    }
  }
  // Headless rviz captures (scripts/capture), if the run made them.
  std::vector<std::string> captures;
  if (std::filesystem::is_directory(dir + "/captures")) {
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/captures")) {
      if (entry.path().extension() == ".png") captures.push_back(entry.path().filename());
    }
  }
  std::sort(captures.begin(), captures.end());
  if (!captures.empty()) {
    out << "## rviz captures\n\n"
        << "config/rviz/aar.rviz on rosbags/sample_contact.bag (experiment dynamic, near "
           "contact): sensed cloud without the boom white, removed boom points magenta, dynamic "
           "reference by "
           "class (both cameras red, left only cyan, right only blue, neither green), shadow "
           "volumes translucent (left blue, right orange), receiver at the estimate orange.\n\n";
    for (const auto& png : captures) out << "![" << png << "](captures/" << png << ")\n\n";
  }
  if (!out) throw std::runtime_error(result.path + ": write failed");
  result.experiments = done;
  return result;
}

}  // namespace aar_eval
