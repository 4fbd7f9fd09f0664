// make_report: DIR/report.md from DIR/<experiment>/frames.csv of each experiment: per-region
// tables in the thesis's layout (average error magnitude and RMS), % difference against the
// baseline, the headline average improvement, misses, and the plots and run details if present.
//   make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "aar_eval/tables.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]\n";
    return 2;
  }
  const std::string dir = argv[1];
  std::vector<std::string> experiments;
  std::stringstream list(argv[2]);
  for (std::string e; std::getline(list, e, ',');) experiments.push_back(e);
  const std::string baseline = argc > 3 ? argv[3] : "";
  try {
    std::map<std::string, std::map<std::string, aar_eval::RegionStats>> stats;
    std::map<std::string, std::vector<aar_eval::FrameRecord>> records;
    std::vector<std::string> done;
    for (const auto& e : experiments) {
      const std::string csv = dir + "/" + e + "/frames.csv";
      if (!std::filesystem::exists(csv)) {
        std::cerr << "make_report: " << csv << " is missing: experiment '" << e << "' left out\n";
        continue;
      }
      records[e] = aar_eval::ReadFrameCsv(csv);
      stats[e] = aar_eval::ComputeRegionStats(records[e]);
      done.push_back(e);
    }
    if (done.empty()) throw std::runtime_error("no experiment has results in " + dir);
    const bool has_baseline = !baseline.empty() && stats.count(baseline);
    if (has_baseline) {  // the baseline's rows come first, the % differences against it after
      done.erase(std::find(done.begin(), done.end(), baseline));
      done.insert(done.begin(), baseline);
    }

    std::ofstream out(dir + "/report.md");
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
        const aar_eval::RegionStats& a = stats[e].at("all");
        const aar_eval::RegionStats& b = stats[baseline].at("all");
        out << "- " << e << ": average improvement over " << baseline << ": " << std::fixed
            << std::setprecision(1) << aar_eval::AverageImprovement(a, b) << "%"
            << (e == "dynamic" ? " (thesis: 74.1%)" : "");
        // Frames by index at 1 ms: path times come from a CSV.
        auto key = [](double t) { return std::llround(t * 1000.0); };
        std::map<long long, const aar_eval::FrameRecord*> theirs;
        for (const auto& f : records[baseline]) {
          if (f.estimated) theirs[key(f.t)] = &f;
        }
        std::vector<aar_eval::FrameRecord> mine_common, theirs_common;
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
          const auto m = aar_eval::ComputeRegionStats(mine_common);
          const auto t = aar_eval::ComputeRegionStats(theirs_common);
          if (m.count("all") && t.count("all")) {
            out << "; on the " << mine_common.size() << " frames both estimated: "
                << aar_eval::AverageImprovement(m.at("all"), t.at("all")) << "%";
          }
        }
        out << "\n";
      }
      out << "\n";
    }
    out << "## Average error magnitude\n\n"
        << aar_eval::MarkdownRegionTable(stats, done, has_baseline ? baseline : "", false);
    out << "\n## RMS error\n\n"
        << aar_eval::MarkdownRegionTable(stats, done, has_baseline ? baseline : "", true);
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
    if (!out) throw std::runtime_error(dir + "/report.md: write failed");
    std::cout << "make_report: wrote " << dir << "/report.md (" << done.size() << " experiments)\n";
  } catch (const std::exception& e) {
    std::cerr << "make_report: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
