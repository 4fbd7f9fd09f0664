#include "aar_eval/tables.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include <aar_geometry/load_error.h>

namespace aar_eval {

const std::array<std::string, 6>& ComponentNames() {
  static const std::array<std::string, 6> names = {"x (m)",      "y (m)",       "z (m)",
                                                   "roll (deg)", "pitch (deg)", "yaw (deg)"};
  return names;
}

std::map<std::string, RegionStats> ComputeRegionStats(const std::vector<FrameRecord>& frames) {
  std::map<std::string, RegionStats> stats;
  std::map<std::string, std::array<double, 6>> sum_sq;
  for (const auto& f : frames) {
    if (f.region == aar_geometry::Region::kOutside) continue;
    for (const std::string& key : {aar_geometry::RegionName(f.region), std::string("all")}) {
      RegionStats& s = stats[key];
      ++s.frames;
      if (!f.estimated) continue;
      ++s.estimated;
      for (int c = 0; c < 6; ++c) {
        s.mean_abs[c] += std::abs(f.error[c]);
        sum_sq[key][c] += f.error[c] * f.error[c];
      }
    }
  }
  for (auto& [key, s] : stats) {
    for (int c = 0; c < 6; ++c) {
      if (s.estimated == 0) {
        s.mean_abs[c] = s.rms[c] = std::numeric_limits<double>::quiet_NaN();
      } else {
        s.mean_abs[c] /= s.estimated;
        s.rms[c] = std::sqrt(sum_sq[key][c] / s.estimated);
      }
    }
  }
  return stats;
}

double PercentDifference(double value, double baseline) {
  if (baseline == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (baseline - value) / baseline * 100.0;
}

double AverageImprovement(const RegionStats& value, const RegionStats& baseline) {
  double sum = 0.0;
  for (int c = 0; c < 6; ++c) sum += PercentDifference(value.mean_abs[c], baseline.mean_abs[c]);
  return sum / 6.0;
}

namespace {
// Before tracking (issue 12) frame CSVs ended at registration_ms; they still load.
const char* const kHeaderBeforeTracking =
    "t,range_m,region,estimated,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,converged,iterations,"
    "rms_m,registration_ms";
}  // namespace

std::string FrameCsvHeader() { return std::string(kHeaderBeforeTracking) + ",track,nees"; }

std::string FrameCsvRow(const FrameRecord& f) {
  std::ostringstream s;
  s << std::setprecision(17) << f.t << ',' << f.range_m << ',' << aar_geometry::RegionName(f.region)
    << ',' << (f.estimated ? 1 : 0);
  for (double e : f.error) s << ',' << (f.estimated ? e : std::numeric_limits<double>::quiet_NaN());
  s << ',' << (f.converged ? 1 : 0) << ',' << f.iterations << ',' << f.rms << ','
    << f.registration_ms << ',' << f.track << ','
    << (f.estimated ? f.nees : std::numeric_limits<double>::quiet_NaN());
  return s.str();
}

void WriteFrameCsv(const std::string& path, const std::vector<FrameRecord>& frames) {
  std::ofstream out(path);
  if (!out) throw aar_geometry::LoadError(path, "cannot be written");
  out << FrameCsvHeader() << "\n";
  for (const auto& f : frames) out << FrameCsvRow(f) << "\n";
  if (!out) throw aar_geometry::LoadError(path, "write failed");
}

std::vector<FrameRecord> ReadFrameCsv(const std::string& path) {
  aar_geometry::CheckReadableFile(path);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const bool before_tracking = line == kHeaderBeforeTracking;
  if (line != FrameCsvHeader() && !before_tracking)
    throw aar_geometry::LoadError(path, "line 1: not a frame CSV header");
  const size_t columns = before_tracking ? 14 : 16;
  std::vector<FrameRecord> frames;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    const std::string where = "line " + std::to_string(number) + ": ";
    if (line.back() == ',') cells.push_back("");  // getline drops a trailing empty cell
    if (cells.size() != columns)
      throw aar_geometry::LoadError(path, where + std::to_string(cells.size()) + " cells, " +
                                              std::to_string(columns) + " expected");
    auto number_at = [&](int i) {
      try {
        size_t used = 0;
        const double v = std::stod(cells[i], &used);
        if (used != cells[i].size()) throw std::invalid_argument("");
        return v;
      } catch (const std::exception&) {
        throw aar_geometry::LoadError(path, where + "'" + cells[i] + "' is not a number");
      }
    };
    FrameRecord f;
    f.t = number_at(0);
    f.range_m = number_at(1);
    f.region = aar_geometry::RegionOfRange(f.range_m);
    if (aar_geometry::RegionName(f.region) != cells[2]) {
      throw aar_geometry::LoadError(
          path, where + "region '" + cells[2] + "' does not match range " + cells[1]);
    }
    f.estimated = number_at(3) != 0.0;
    for (int c = 0; c < 6; ++c) f.error[c] = f.estimated ? number_at(4 + c) : 0.0;
    f.converged = number_at(10) != 0.0;
    f.iterations = static_cast<int>(number_at(11));
    f.rms = number_at(12);
    f.registration_ms = number_at(13);
    if (!before_tracking) {
      f.track = cells[14];
      f.nees = cells[15] == "nan" ? std::numeric_limits<double>::quiet_NaN() : number_at(15);
    }
    frames.push_back(f);
  }
  return frames;
}

std::string MarkdownRegionTable(
    const std::map<std::string, std::map<std::string, RegionStats>>& by_experiment,
    const std::vector<std::string>& order, const std::string& baseline, bool rms) {
  static const std::vector<std::pair<std::string, std::string>> regions = {
      {"A", "Region A (175-70 m)"},
      {"B", "Region B (70-38 m)"},
      {"C", "Region C (38-32 m)"},
      {"all", "Whole approach"}};
  std::ostringstream s;
  s << std::fixed;
  s << "| region | experiment | frames (estimated) |";
  for (const auto& c : ComponentNames()) s << ' ' << c << " |";
  s << "\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [key, title] : regions) {
    for (const auto& name : order) {
      const auto& stats = by_experiment.at(name);
      const auto it = stats.find(key);
      if (it == stats.end()) continue;
      const RegionStats& r = it->second;
      s << "| " << title << " | " << name << (rms ? " RMS" : " average error magnitude") << " | "
        << r.frames << " (" << r.estimated << ") |";
      for (int c = 0; c < 6; ++c)
        s << ' ' << std::setprecision(3) << (rms ? r.rms[c] : r.mean_abs[c]) << " |";
      s << "\n";
      if (!baseline.empty() && name != baseline && by_experiment.count(baseline) &&
          by_experiment.at(baseline).count(key)) {
        const RegionStats& b = by_experiment.at(baseline).at(key);
        s << "| " << title << " | % difference, " << name << " against " << baseline << " | |";
        for (int c = 0; c < 6; ++c) {
          s << ' ' << std::setprecision(2)
            << PercentDifference(rms ? r.rms[c] : r.mean_abs[c], rms ? b.rms[c] : b.mean_abs[c])
            << " |";
        }
        s << "\n";
      }
    }
  }
  return s.str();
}

}  // namespace aar_eval
