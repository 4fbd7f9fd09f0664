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

#include "aar_eval/integrity.h"
#include "aar_eval/tables.h"
#include "integrity_section.h"
#include "markdown.h"
#include "run_record.h"
#include "visibility_section.h"

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

// records[approach][experiment]
using ApproachRecords = std::map<std::string, std::map<std::string, std::vector<FrameRecord>>>;
// An experiment's region statistics by approach: [approach][region].
using ApproachStats = std::map<std::string, std::map<std::string, RegionStats>>;
// stats[experiment][approach][region]
using SuiteStats = std::map<std::string, ApproachStats>;

// An experiment's row of a table over approaches.
struct ExperimentRow {
  std::string experiment;
  int approaches = 0;
  std::map<std::string, Interval> intervals;  // by region key or by component name
};

// The first columns of the tables over approaches: "experiment" and "approaches".
Columns<ExperimentRow> ExperimentColumns() {
  return {{"experiment", Align::kLeft, [](const ExperimentRow& r) { return r.experiment; }},
          {"approaches", Align::kRight,
           [](const ExperimentRow& r) { return std::to_string(r.approaches); }}};
}

// Per region, its interval of the row with `digits` decimals and `suffix`, then the interval's
// verdict if `verdict`.
void AddRegionColumns(Columns<ExperimentRow>& columns, int digits, const std::string& suffix,
                      bool verdict) {
  for (const auto& region : RegionTitles()) {
    const std::string key = region.first;
    columns.push_back({RegionColumnHeader(key), Align::kRight, [=](const ExperimentRow& r) {
                         const Interval& i = r.intervals.at(key);
                         return FormatInterval(i, digits) + (i.n ? suffix : "") +
                                (verdict ? Verdict(i) : "");
                       }});
  }
}

// The approaches under DIR/approaches (sorted, into `result`) and their experiments' frames;
// an approach that lacks an experiment, or has fewer of its frames than of another or than its
// run planned, is incomplete.
ApproachRecords ReadApproaches(const SuiteReportOptions& options, SuiteReportResult& result) {
  namespace fs = std::filesystem;
  const fs::path approaches_dir = fs::path(options.dir) / "approaches";
  if (fs::is_directory(approaches_dir)) {
    for (const auto& entry : fs::directory_iterator(approaches_dir))
      if (entry.is_directory()) result.approaches.push_back(entry.path().filename().string());
  }
  std::sort(result.approaches.begin(), result.approaches.end());
  ApproachRecords records;
  for (const auto& a : result.approaches) {
    size_t most = 0;
    for (const auto& e : options.experiments) {
      const fs::path csv = approaches_dir / a / e / "frames.csv";
      if (!fs::exists(csv)) continue;
      records[a][e] = ReadFrameCsv(csv.string());
      most = std::max(most, records[a][e].size());
    }
    for (const auto& e : options.experiments) {
      const std::string key = a + "/" + e;
      const size_t flown = records[a].count(e) ? records[a][e].size() : 0;
      std::string why = ShortOfPlan(ReadPlannedRun((approaches_dir / key).string()), flown);
      if (!records[a].count(e))
        why = "not flown" + (why.empty() ? "" : ": " + why);
      else if (why.empty() && flown < most)
        why = std::to_string(flown) + " frames, another experiment " + std::to_string(most);
      if (why.empty()) continue;
      result.incomplete.push_back(key);
      result.incomplete_why[key] = why;
    }
  }
  const bool any =
      std::any_of(records.begin(), records.end(), [](const auto& r) { return !r.second.empty(); });
  if (!any) throw std::runtime_error("no approach has results in " + approaches_dir.string());
  return records;
}

// The title, the run, what is incomplete, the approaches' settings (DIR/approaches.csv) and how
// to read the figures.
void WriteIntroduction(std::ostream& out, const SuiteReportOptions& options,
                       const SuiteReportResult& result) {
  out << "# AAR suite report\n\n";
  WriteRunSection(out, options.dir);
  if (!result.incomplete.empty()) {
    out << "**INCOMPLETE:** missing or short: ";
    for (size_t i = 0; i < result.incomplete.size(); ++i) {
      const std::string& key = result.incomplete[i];
      out << (i ? ", " : "") << key << " (" << result.incomplete_why.at(key) << ")";
    }
    out << ". Each statistic is over the approaches that have the experiment's results.\n\n";
  }
  std::ifstream settings(options.dir + "/approaches.csv");
  if (settings) {
    out << "## Approaches\n\n";
    bool header = true;
    for (std::string line; std::getline(settings, line);) {
      if (line.empty()) continue;
      std::vector<std::string> cells(1);
      for (char c : line) {
        if (c == ',')
          cells.emplace_back();
        else
          cells.back().push_back(c);
      }
      WriteMarkdownRow(out, cells);
      if (header) WriteMarkdownRule(out, std::vector<Align>(cells.size(), Align::kLeft));
      header = false;
    }
    out << "\n";
  }
  const int percent = static_cast<int>(std::lround(options.confidence * 100.0));
  out << "Each figure is the mean over approaches of that approach's figure, with its " << percent
      << " % Student-t confidence interval in brackets; approaches are independent samples.\n\n";
}

// Each experiment's runs, one per approach that has it, in the options' order.
std::vector<ExperimentRuns> RunsPerExperiment(const SuiteReportOptions& options,
                                              const ApproachRecords& records) {
  std::vector<ExperimentRuns> out;
  for (const auto& e : options.experiments) {
    ExperimentRuns runs{e, {}};
    for (const auto& [a, by_e] : records) {
      const auto it = by_e.find(e);
      if (it != by_e.end()) runs.second.push_back(&it->second);
    }
    out.push_back(runs);
  }
  return out;
}

// A line per experiment with frames outside the regions, over all approaches: in no table.
void WriteOutsideNotes(std::ostream& out, const std::vector<ExperimentRuns>& experiments) {
  bool any = false;
  for (const auto& [e, runs] : experiments) {
    const std::string note = OutsideRegionsNote(e, runs);
    if (!note.empty()) out << (any ? "" : "\n") << "- " << note << "\n";
    any |= !note.empty();
  }
}

// Share of frames with an estimate of their own, per region.
void WriteCoverage(std::ostream& out, const SuiteReportOptions& options, const SuiteStats& stats) {
  out << "## Coverage\n\nShare of frames with an estimate of their own (%; the interval clipped "
         "to 0-100).\n\n";
  Columns<ExperimentRow> columns = ExperimentColumns();
  AddRegionColumns(columns, 1, "", false);
  WriteTableHead(out, columns);
  for (const auto& e : options.experiments) {
    if (!stats.count(e)) continue;
    ExperimentRow row{e, static_cast<int>(stats.at(e).size()), {}};
    for (const auto& [key, title] : RegionTitles()) {
      std::vector<double> share;
      for (const auto& [a, s] : stats.at(e)) {
        const auto it = s.find(key);
        share.push_back(it == s.end() || it->second.frames == 0
                            ? Nan()
                            : 100.0 * it->second.estimated / it->second.frames);
      }
      Interval i = MeanInterval(share, options.confidence);
      i.low = std::max(i.low, 0.0);  // a share: the t interval clipped to what can be
      i.high = std::min(i.high, 100.0);
      row.intervals[key] = i;
    }
    WriteTableRow(out, columns, row);
  }
}

// Per region, each component's average error magnitude.
void WriteErrorMagnitudes(std::ostream& out, const SuiteReportOptions& options,
                          const SuiteStats& stats) {
  out << "\n## Average error magnitude\n\nPer approach over the frames it estimated; then the "
         "mean over approaches.\n";
  Columns<ExperimentRow> columns = ExperimentColumns();
  for (const std::string& component : ComponentNames()) {
    columns.push_back({component, Align::kRight, [=](const ExperimentRow& r) {
                         return FormatInterval(r.intervals.at(component), 3);
                       }});
  }
  for (const auto& [key, title] : RegionTitles()) {
    out << "\n### " << title << "\n\n";
    WriteTableHead(out, columns);
    for (const auto& e : options.experiments) {
      if (!stats.count(e)) continue;
      std::array<std::vector<double>, 6> samples;
      for (const auto& [a, s] : stats.at(e)) {
        const auto it = s.find(key);
        for (int c = 0; c < 6; ++c)
          samples[c].push_back(it == s.end() ? Nan() : it->second.mean_abs[c]);
      }
      ExperimentRow row{e, MeanInterval(samples[0], options.confidence).n, {}};
      for (int c = 0; c < 6; ++c)
        row.intervals[ComponentNames()[c]] = MeanInterval(samples[c], options.confidence);
      WriteTableRow(out, columns, row);
    }
  }
}

// An experiment's longest wrong locks over approaches.
struct WrongLockRow {
  std::string experiment;
  int approaches = 0;
  int over_one_second = 0;
  Interval seconds;
  std::string longest = "-";  // "1.2 (approach 03, from t = 4.5 s)"
};

// The longest wrong lock of each experiment's approaches (LongestWrongLock).
void WriteWrongLocks(std::ostream& out, const SuiteReportOptions& options,
                     const ApproachRecords& records) {
  out << "\n## Wrong lock (regions B and C)\n\nPer approach, the longest run of frames whose "
         "own estimate is more than 0.5 m or 2 deg off (a frame without an estimate ends a run); "
         "how many approaches have one longer than 1 s, the mean over approaches, and the "
         "longest of all.\n\n";
  const Columns<WrongLockRow> columns = {
      {"experiment", Align::kLeft, [](const WrongLockRow& r) { return r.experiment; }},
      {"approaches", Align::kRight,
       [](const WrongLockRow& r) { return std::to_string(r.approaches); }},
      {"longer than 1 s", Align::kRight,
       [](const WrongLockRow& r) { return std::to_string(r.over_one_second); }},
      {"longest per approach (s)", Align::kRight,
       [](const WrongLockRow& r) { return FormatInterval(r.seconds, 2); }},
      {"longest (s)", Align::kLeft, [](const WrongLockRow& r) { return r.longest; }}};
  WriteTableHead(out, columns);
  for (const auto& e : options.experiments) {
    WrongLockRow row;
    row.experiment = e;
    std::vector<double> seconds;
    double most = 0.0;
    for (const auto& [a, by_e] : records) {
      if (!by_e.count(e)) continue;
      const WrongLock lock = LongestWrongLock(by_e.at(e));
      seconds.push_back(lock.seconds);
      row.over_one_second += lock.seconds > 1.0;
      if (lock.seconds > most) {
        most = lock.seconds;
        row.longest = Fixed(lock.seconds, 1) + " (approach " + a +
                      ", from t = " + Fixed(lock.start_t, 1) + " s)";
      }
    }
    if (seconds.empty()) continue;
    row.approaches = static_cast<int>(seconds.size());
    row.seconds = MeanInterval(seconds, options.confidence);
    WriteTableRow(out, columns, row);
  }
}

// Per baseline, each other experiment's paired average improvement over it, per region.
void WritePairedImprovements(std::ostream& out, const SuiteReportOptions& options,
                             const ApproachRecords& records, const SuiteStats& stats) {
  Columns<ExperimentRow> columns = ExperimentColumns();
  AddRegionColumns(columns, 1, " %", true);
  for (const auto& baseline : options.baselines) {
    if (!stats.count(baseline)) continue;
    out << "\n## Paired improvement over " << baseline << "\n\nPer approach, the thesis's average "
        << "improvement (the mean over the six components of the % difference of the average "
           "error magnitude) on the frames both it and "
        << baseline
        << " estimated; then the mean over approaches. \"better\" or \"worse\": the interval "
           "excludes 0; \"unresolved\": it does not.\n\n";
    WriteTableHead(out, columns);
    for (const auto& e : options.experiments) {
      if (e == baseline || !stats.count(e)) continue;
      std::map<std::string, std::vector<double>> gain;
      ExperimentRow row{e, 0, {}};
      for (const auto& [a, by_e] : records) {
        if (!by_e.count(e) || !by_e.count(baseline)) continue;
        ++row.approaches;
        const auto paired = ComputePairedRegionStats(by_e.at(e), by_e.at(baseline));
        for (const auto& [key, title] : RegionTitles()) {
          const auto it = paired.value.find(key);
          gain[key].push_back(it == paired.value.end() || it->second.estimated == 0
                                  ? Nan()
                                  : AverageImprovement(it->second, paired.baseline.at(key)));
        }
      }
      for (const auto& [key, title] : RegionTitles())
        row.intervals[key] = MeanInterval(gain[key], options.confidence);
      WriteTableRow(out, columns, row);
    }
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
  SuiteReportResult result;
  result.path = options.dir + "/suite.md";
  const ApproachRecords records = ReadApproaches(options, result);
  SuiteStats stats;
  for (const auto& [a, by_e] : records)
    for (const auto& [e, frames] : by_e) stats[e][a] = ComputeRegionStats(frames);

  std::ofstream out(result.path);
  WriteIntroduction(out, options, result);
  WriteCoverage(out, options, stats);
  const std::vector<ExperimentRuns> runs = RunsPerExperiment(options, records);
  WriteOutsideNotes(out, runs);
  const std::string visibility = VisibilitySection(runs);
  if (!visibility.empty()) out << "\n" << visibility;
  WriteErrorMagnitudes(out, options, stats);
  WriteWrongLocks(out, options, records);
  WritePairedImprovements(out, options, records, stats);
  const IntegrityOptions integrity{options.protection_level_scale};
  std::map<std::string, std::map<std::string, IntegrityStats>> summed;  // [experiment][region]
  for (const auto& [a, by_e] : records) {
    for (const auto& [e, frames] : by_e) {
      for (const auto& [key, s] : ComputeIntegrityStats(frames, integrity)) summed[e][key] += s;
    }
  }
  WriteIntegritySection(out, options.experiments, summed, integrity, options.dir,
                        "Summed over all approaches: counts added, the NEES mean over every frame "
                        "with a NEES, availability over every frame.");
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw std::runtime_error(result.path + ": write failed");
  return result;
}

}  // namespace aar_eval
