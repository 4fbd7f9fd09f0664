#include "aar_eval/suite.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/students_t.hpp>

#include "aar_eval/tables.h"

namespace aar_eval {
namespace {

double Nan() { return std::numeric_limits<double>::quiet_NaN(); }

// Whether the interval of a % improvement settles the sign.
std::string Verdict(const Interval& i) {
  if (i.n < 2) return "";
  if (i.low > 0.0) return " better";
  if (i.high < 0.0) return " worse";
  return " unresolved";
}

// The longest wrong lock of each experiment's approaches (LongestWrongLock).
void WriteWrongLocks(
    std::ostream& out, const SuiteReportOptions& options,
    const std::map<std::string, std::map<std::string, std::vector<FrameRecord>>>& records) {
  out << "\n## Wrong lock (regions B and C)\n\nPer approach, the longest run of frames whose "
         "own estimate is more than 0.5 m or 2 deg off (a frame without an estimate ends a run); "
         "how many approaches have one longer than 1 s, the mean over approaches, and the "
         "longest of all.\n\n"
      << "| experiment | approaches | longer than 1 s | longest per approach (s) | longest (s) "
         "|\n|---|---:|---:|---:|---|\n";
  for (const auto& e : options.experiments) {
    std::vector<double> seconds;
    int over = 0;
    std::string where = "-";
    double most = 0.0;
    for (const auto& [a, by_e] : records) {
      if (!by_e.count(e)) continue;
      const WrongLock lock = LongestWrongLock(by_e.at(e));
      seconds.push_back(lock.seconds);
      over += lock.seconds > 1.0;
      if (lock.seconds > most) {
        most = lock.seconds;
        std::ostringstream s;
        s << std::fixed << std::setprecision(1) << lock.seconds << " (approach " << a
          << ", from t = " << lock.start_t << " s)";
        where = s.str();
      }
    }
    if (seconds.empty()) continue;
    out << "| " << e << " | " << seconds.size() << " | " << over << " | "
        << FormatInterval(MeanInterval(seconds, options.confidence), 2) << " | " << where << " |\n";
  }
}

}  // namespace

std::string FormatInterval(const Interval& i, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits);
  if (i.n == 0) return "-";
  s << i.mean;
  if (i.n == 1)
    s << " (n = 1)";
  else
    s << " [" << i.low << ", " << i.high << "]";
  return s.str();
}

Interval MeanInterval(const std::vector<double>& samples, double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("confidence must be in (0, 1)");
  std::vector<double> v;
  for (double x : samples)
    if (std::isfinite(x)) v.push_back(x);
  Interval out;
  out.n = static_cast<int>(v.size());
  if (v.empty()) return out;
  double sum = 0.0;
  for (double x : v) sum += x;
  out.mean = sum / out.n;
  out.low = out.high = out.mean;
  if (out.n < 2) return out;
  double ss = 0.0;
  for (double x : v) ss += (x - out.mean) * (x - out.mean);
  const double sem = std::sqrt(ss / (out.n - 1) / out.n);
  const boost::math::students_t t(out.n - 1);
  const double half = boost::math::quantile(t, 0.5 + confidence / 2.0) * sem;
  out.low = out.mean - half;
  out.high = out.mean + half;
  return out;
}

SuiteReportResult WriteSuiteReport(const SuiteReportOptions& options) {
  namespace fs = std::filesystem;
  const std::string& dir = options.dir;
  SuiteReportResult result;
  result.path = dir + "/suite.md";
  const fs::path approaches_dir = fs::path(dir) / "approaches";
  if (fs::is_directory(approaches_dir)) {
    for (const auto& entry : fs::directory_iterator(approaches_dir))
      if (entry.is_directory()) result.approaches.push_back(entry.path().filename().string());
  }
  std::sort(result.approaches.begin(), result.approaches.end());

  // records[approach][experiment]
  std::map<std::string, std::map<std::string, std::vector<FrameRecord>>> records;
  for (const auto& a : result.approaches) {
    size_t most = 0;
    for (const auto& e : options.experiments) {
      const fs::path csv = approaches_dir / a / e / "frames.csv";
      if (!fs::exists(csv)) continue;
      records[a][e] = ReadFrameCsv(csv.string());
      most = std::max(most, records[a][e].size());
    }
    for (const auto& e : options.experiments) {
      if (!records[a].count(e) || records[a][e].size() < most)
        result.incomplete.push_back(a + "/" + e);
    }
  }
  const bool any =
      std::any_of(records.begin(), records.end(), [](const auto& r) { return !r.second.empty(); });
  if (!any) throw std::runtime_error("no approach has results in " + approaches_dir.string());

  std::ofstream out(result.path);
  out << "# AAR suite report\n\n";
  std::ifstream run(dir + "/run.txt");
  if (run && run.peek() != std::ifstream::traits_type::eof())
    out << "## Run\n\n```\n" << run.rdbuf() << "```\n\n";
  if (!result.incomplete.empty()) {
    out << "**INCOMPLETE:** missing or short: ";
    for (size_t i = 0; i < result.incomplete.size(); ++i)
      out << (i ? ", " : "") << result.incomplete[i];
    out << ". Each statistic is over the approaches that have the experiment's results.\n\n";
  }
  std::ifstream settings(dir + "/approaches.csv");
  if (settings) {
    out << "## Approaches\n\n";
    std::string line;
    bool header = true;
    while (std::getline(settings, line)) {
      if (line.empty()) continue;
      std::string row = "| ";
      for (char c : line) row += c == ',' ? std::string(" | ") : std::string(1, c);
      out << row << " |\n";
      if (header) {
        const size_t columns = std::count(line.begin(), line.end(), ',') + 1;
        out << "|";
        for (size_t i = 0; i < columns; ++i) out << "---|";
        out << "\n";
        header = false;
      }
    }
    out << "\n";
  }
  const int percent = static_cast<int>(std::lround(options.confidence * 100.0));
  out << "Each figure is the mean over approaches of that approach's figure, with its " << percent
      << " % Student-t confidence interval in brackets; approaches are independent samples.\n\n";

  // stats[experiment][approach] per region
  std::map<std::string, std::map<std::string, std::map<std::string, RegionStats>>> stats;
  for (const auto& [a, by_e] : records)
    for (const auto& [e, frames] : by_e) stats[e][a] = ComputeRegionStats(frames);

  out << "## Coverage\n\nShare of frames with an estimate of their own (%; the interval clipped "
         "to 0-100).\n\n"
      << "| experiment | approaches | region A | region B | region C | whole approach |\n"
      << "|---|---:|---:|---:|---:|---:|\n";
  for (const auto& e : options.experiments) {
    if (!stats.count(e)) continue;
    out << "| " << e << " | " << stats[e].size() << " |";
    for (const auto& [key, title] : RegionTitles()) {
      std::vector<double> share;
      for (const auto& [a, s] : stats[e]) {
        const auto it = s.find(key);
        share.push_back(it == s.end() || it->second.frames == 0
                            ? Nan()
                            : 100.0 * it->second.estimated / it->second.frames);
      }
      Interval i = MeanInterval(share, options.confidence);
      i.low = std::max(i.low, 0.0);  // a share: the t interval clipped to what can be
      i.high = std::min(i.high, 100.0);
      out << ' ' << FormatInterval(i, 1) << " |";
    }
    out << "\n";
  }

  out << "\n## Average error magnitude\n\nPer approach over the frames it estimated; then the "
         "mean over approaches.\n";
  for (const auto& [key, title] : RegionTitles()) {
    out << "\n### " << title << "\n\n| experiment | approaches |";
    for (const auto& c : ComponentNames()) out << ' ' << c << " |";
    out << "\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const auto& e : options.experiments) {
      if (!stats.count(e)) continue;
      std::array<std::vector<double>, 6> samples;
      for (const auto& [a, s] : stats[e]) {
        const auto it = s.find(key);
        for (int c = 0; c < 6; ++c)
          samples[c].push_back(it == s.end() ? Nan() : it->second.mean_abs[c]);
      }
      out << "| " << e << " | " << MeanInterval(samples[0], options.confidence).n << " |";
      for (int c = 0; c < 6; ++c)
        out << ' ' << FormatInterval(MeanInterval(samples[c], options.confidence), 3) << " |";
      out << "\n";
    }
  }

  WriteWrongLocks(out, options, records);

  for (const auto& baseline : options.baselines) {
    if (!stats.count(baseline)) continue;
    out << "\n## Paired improvement over " << baseline << "\n\nPer approach, the thesis's average "
        << "improvement (the mean over the six components of the % difference of the average "
           "error magnitude) on the frames both it and "
        << baseline
        << " estimated; then the mean over approaches. \"better\" or \"worse\": the interval "
           "excludes 0; \"unresolved\": it does not.\n\n"
        << "| experiment | approaches | region A | region B | region C | whole approach |\n"
        << "|---|---:|---:|---:|---:|---:|\n";
    for (const auto& e : options.experiments) {
      if (e == baseline || !stats.count(e)) continue;
      std::map<std::string, std::vector<double>> gain;
      int paired = 0;
      for (const auto& [a, by_e] : records) {
        if (!by_e.count(e) || !by_e.count(baseline)) continue;
        ++paired;
        const auto paired_stats = ComputePairedRegionStats(by_e.at(e), by_e.at(baseline));
        const auto& m = paired_stats.value;
        const auto& b = paired_stats.baseline;
        for (const auto& [key, title] : RegionTitles()) {
          const auto it = m.find(key);
          gain[key].push_back(it == m.end() || it->second.estimated == 0
                                  ? Nan()
                                  : AverageImprovement(it->second, b.at(key)));
        }
      }
      out << "| " << e << " | " << paired << " |";
      for (const auto& [key, title] : RegionTitles()) {
        const Interval i = MeanInterval(gain[key], options.confidence);
        out << ' ' << FormatInterval(i, 1) << (i.n ? " %" : "") << Verdict(i) << " |";
      }
      out << "\n";
    }
  }
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw std::runtime_error(result.path + ": write failed");
  return result;
}

}  // namespace aar_eval
