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
  std::map<std::string, std::vector<FrameRecord>> records;
  std::vector<std::string> done;
  for (const auto& e : options.experiments) {
    const std::string csv = dir + "/" + e + "/frames.csv";
    if (!std::filesystem::exists(csv)) {
      result.missing.push_back(e);
      continue;
    }
    records[e] = ReadFrameCsv(csv);
    done.push_back(e);
  }
  if (done.empty()) throw std::runtime_error("no experiment has results in " + dir);
  const bool has_baseline = !baseline.empty() && records.count(baseline);
  if (has_baseline) {  // the baseline's rows come first, the % differences against it after
    done.erase(std::find(done.begin(), done.end(), baseline));
    done.insert(done.begin(), baseline);
  }
  std::map<std::string, std::map<std::string, RegionStats>> stats;
  bool any_miss = false;
  for (const auto& e : done) {
    stats[e] = ComputeRegionStats(records[e]);
    if (stats[e].count("all") && stats[e].at("all").estimated < stats[e].at("all").frames)
      any_miss = true;
  }

  std::ofstream out(result.path);
  out << "# AAR pose estimation report\n\n";
  std::ifstream run(dir + "/run.txt");
  if (run && run.peek() != std::ifstream::traits_type::eof())
    out << "## Run\n\n```\n" << run.rdbuf() << "```\n\n";
  out << "Errors are estimate minus truth in the true receiver body frame (x, y, z in metres) and "
         "roll, pitch, yaw of R_truth^T R_estimate (degrees). An experiment's rows average over "
         "the frames it estimated; \"frames (estimated)\" counts both. Each % difference row "
         "compares the experiment with the baseline on the same frames, those both estimated, "
         "and counts them: (baseline - value) / baseline x 100, positive is better.\n\n";

  out << "## Coverage\n\nFrames with an estimate of this frame, of all frames, per region.\n\n"
      << "| experiment | region A | region B | region C | whole approach |\n"
      << "|---|---:|---:|---:|---:|\n";
  for (const auto& e : done) {
    out << "| " << e << " |";
    for (const auto& [key, title] : RegionTitles()) {
      const auto it = stats[e].find(key);
      if (it == stats[e].end())
        out << " - |";
      else
        out << ' ' << it->second.estimated << " / " << it->second.frames << " |";
    }
    out << "\n";
  }
  out << "\n";
  if (any_miss) {
    out << "Miss policy: a frame without an estimate of its own is a miss. It is in no average "
           "of the tables below; the section \"As published\" scores instead what a live "
           "system publishes, the last estimate held through each miss.\n\n";
  }

  if (has_baseline) {
    out << "## Headline\n\nThe thesis's statistic: the mean over the six components, whole "
           "approach, of the % difference of the average error magnitude against "
        << baseline << ", on the frames both estimated.\n\n";
    for (const auto& e : done) {
      if (e == baseline) continue;
      const auto paired = ComputePairedRegionStats(records[e], records[baseline]);
      const auto& mine = paired.value;
      const auto& theirs = paired.baseline;
      out << "- " << e << ": average improvement over " << baseline << ": ";
      if (!mine.count("all") || mine.at("all").estimated == 0) {
        out << "no frame both estimated\n";
        continue;
      }
      const int n = mine.at("all").estimated;
      const int frames = stats[e].count("all") ? stats[e].at("all").frames : 0;
      out << std::fixed << std::setprecision(1)
          << AverageImprovement(mine.at("all"), theirs.at("all")) << "%";
      const int e_estimated = stats[e].at("all").estimated;
      const int b_estimated =
          stats[baseline].count("all") ? stats[baseline].at("all").estimated : 0;
      if (n == frames && e_estimated == frames && b_estimated == frames)
        out << " on every frame (" << n << ")";
      else
        out << " on the " << n << " frames both estimated (" << e << " estimated " << e_estimated
            << " of " << frames << ", " << baseline << " " << b_estimated << ")";
      if (e == "dynamic") out << " (thesis: 74.1%, on every frame)";
      if (n != frames) {
        const auto held =
            ComputePairedRegionStats(records[e], records[baseline], ErrorPolicy::kHoldLast);
        const auto& hm = held.value;
        const auto& hb = held.baseline;
        if (hm.count("all") && hm.at("all").estimated > 0) {
          out << "; as published (the last estimate held through misses): "
              << AverageImprovement(hm.at("all"), hb.at("all")) << "% on " << hm.at("all").estimated
              << " frames";
        }
      }
      out << "\n";
    }
    out << "\n";
  }
  const std::string b = has_baseline ? baseline : "";
  out << "## Average error magnitude\n\n" << MarkdownRegionTable(records, done, b, false);
  out << "\n## RMS error\n\n" << MarkdownRegionTable(records, done, b, true);
  if (any_miss) {
    out << "\n## As published: the last estimate held through misses\n\nAverage error "
           "magnitude of what a live system publishes on each frame: its estimate, or on a miss "
           "the last estimate again, against this frame's truth. Frames before the first "
           "estimate have nothing published and are left out; \"frames (published)\" counts "
           "both.\n\n"
        << MarkdownRegionTable(records, done, b, false, ErrorPolicy::kHoldLast);
  }
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
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw std::runtime_error(result.path + ": write failed");
  result.experiments = done;
  return result;
}

}  // namespace aar_eval
