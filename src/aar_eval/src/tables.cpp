#include "aar_eval/tables.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace aar_eval {

const std::array<std::string, 6>& ComponentNames() {
  static const std::array<std::string, 6> names = {"x (m)",      "y (m)",       "z (m)",
                                                   "roll (deg)", "pitch (deg)", "yaw (deg)"};
  return names;
}

namespace {

bool HasError(const FrameRecord& f, ErrorPolicy policy) {
  return policy == ErrorPolicy::kEstimated ? f.estimated : f.published;
}

const std::array<double, 6>& ErrorOf(const FrameRecord& f, ErrorPolicy policy) {
  return policy == ErrorPolicy::kEstimated ? f.error : f.published_error;
}

}  // namespace

const std::vector<std::pair<std::string, std::string>>& RegionTitles() {
  static const std::vector<std::pair<std::string, std::string>> regions = {
      {"A", "Region A (175-70 m)"},
      {"B", "Region B (70-38 m)"},
      {"C", "Region C (38-32 m)"},
      {"all", "Whole approach"}};
  return regions;
}

std::map<std::string, RegionStats> ComputeRegionStats(const std::vector<FrameRecord>& frames,
                                                      ErrorPolicy policy) {
  std::map<std::string, RegionStats> stats;
  std::map<std::string, std::array<double, 6>> sum_sq;
  for (const auto& f : frames) {
    if (f.region == aar_geometry::Region::kOutside) continue;
    for (const std::string& key : {aar_geometry::RegionName(f.region), std::string("all")}) {
      RegionStats& s = stats[key];
      ++s.frames;
      if (!HasError(f, policy)) continue;
      ++s.estimated;
      const auto& error = ErrorOf(f, policy);
      for (int c = 0; c < 6; ++c) {
        s.mean_abs[c] += std::abs(error[c]);
        sum_sq[key][c] += error[c] * error[c];
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

std::pair<std::vector<FrameRecord>, std::vector<FrameRecord>> CommonFrames(
    const std::vector<FrameRecord>& a, const std::vector<FrameRecord>& b, ErrorPolicy policy) {
  auto key = [](double t) { return std::llround(t * 1000.0); };  // path times come from a CSV
  std::map<long long, const FrameRecord*> in_b;
  for (const auto& f : b) {
    if (HasError(f, policy)) in_b[key(f.t)] = &f;
  }
  std::pair<std::vector<FrameRecord>, std::vector<FrameRecord>> common;
  for (const auto& f : a) {
    const auto it = in_b.find(key(f.t));
    if (!HasError(f, policy) || it == in_b.end()) continue;
    common.first.push_back(f);
    common.second.push_back(*it->second);
  }
  return common;
}

PairedRegionStats ComputePairedRegionStats(const std::vector<FrameRecord>& a,
                                           const std::vector<FrameRecord>& b, ErrorPolicy policy) {
  const auto common = CommonFrames(a, b, policy);
  return {ComputeRegionStats(common.first, policy), ComputeRegionStats(common.second, policy)};
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

std::string MarkdownRegionTable(const std::map<std::string, std::vector<FrameRecord>>& records,
                                const std::vector<std::string>& order, const std::string& baseline,
                                bool rms, ErrorPolicy policy) {
  const char* counted = policy == ErrorPolicy::kEstimated ? "estimated" : "published";
  std::map<std::string, std::map<std::string, RegionStats>> stats;
  std::map<std::string, PairedRegionStats> paired;  // against the baseline
  const bool compare = !baseline.empty() && records.count(baseline);
  for (const auto& name : order) {
    stats[name] = ComputeRegionStats(records.at(name), policy);
    if (!compare || name == baseline) continue;
    paired[name] = ComputePairedRegionStats(records.at(name), records.at(baseline), policy);
  }
  std::ostringstream s;
  s << std::fixed;
  s << "| region | experiment | frames (" << counted << ") |";
  for (const auto& c : ComponentNames()) s << ' ' << c << " |";
  s << "\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [key, title] : RegionTitles()) {
    for (const auto& name : order) {
      const auto it = stats[name].find(key);
      if (it == stats[name].end()) continue;
      const RegionStats& r = it->second;
      s << "| " << title << " | " << name << (rms ? " RMS" : " average error magnitude") << " | "
        << r.frames << " (" << r.estimated << ") |";
      for (int c = 0; c < 6; ++c)
        s << ' ' << std::setprecision(3) << (rms ? r.rms[c] : r.mean_abs[c]) << " |";
      s << "\n";
      if (!paired.count(name)) continue;
      const auto mine = paired[name].value.find(key);
      s << "| " << title << " | % difference, " << name << " against " << baseline
        << ", same frames | ";
      if (mine == paired[name].value.end() || mine->second.estimated == 0) {
        s << "0 | no frame both " << counted << " |||||\n";
        continue;
      }
      const RegionStats& m = mine->second;
      const RegionStats& b = paired[name].baseline.at(key);
      s << m.estimated << " |";
      for (int c = 0; c < 6; ++c) {
        s << ' ' << std::setprecision(2)
          << PercentDifference(rms ? m.rms[c] : m.mean_abs[c], rms ? b.rms[c] : b.mean_abs[c])
          << " |";
      }
      s << "\n";
    }
  }
  return s.str();
}

double PositionErrorNorm(const FrameRecord& f) {
  return std::sqrt(f.error[0] * f.error[0] + f.error[1] * f.error[1] + f.error[2] * f.error[2]);
}

WrongLock LongestWrongLock(const std::vector<FrameRecord>& frames, double max_position_m,
                           double max_angle_deg) {
  auto wrong = [&](const FrameRecord& f) {
    if (f.region != aar_geometry::Region::kB && f.region != aar_geometry::Region::kC) return false;
    if (!f.estimated) return false;
    const double position = PositionErrorNorm(f);
    const double angle =
        std::max({std::abs(f.error[3]), std::abs(f.error[4]), std::abs(f.error[5])});
    return position > max_position_m || angle > max_angle_deg;
  };
  WrongLock longest;
  for (size_t i = 0; i < frames.size();) {
    if (!wrong(frames[i])) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end < frames.size() && wrong(frames[end])) ++end;
    const double spacing = frames.size() > 1 ? frames[1].t - frames[0].t : 0.0;
    const double stop = end < frames.size() ? frames[end].t : frames.back().t + spacing;
    if (stop - frames[i].t > longest.seconds)
      longest = {stop - frames[i].t, frames[i].t, static_cast<int>(end - i)};
    i = end;
  }
  return longest;
}

}  // namespace aar_eval
