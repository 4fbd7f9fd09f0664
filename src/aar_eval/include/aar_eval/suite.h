#pragma once

#include <map>
#include <string>
#include <vector>

namespace aar_eval {

// The mean of independent samples (one per approach) with its two-sided Student-t confidence
// interval. With fewer than two samples there is no interval (low = high = mean).
struct Interval {
  int n = 0;
  double mean = 0.0;
  double low = 0.0;
  double high = 0.0;
};
// NaN samples are left out. `confidence` in (0, 1).
Interval MeanInterval(const std::vector<double>& samples, double confidence = 0.95);
// "mean [low, high]" at `digits` decimals, "mean (n = 1)" with one sample, "-" with none.
std::string FormatInterval(const Interval& interval, int digits);

struct SuiteReportOptions {
  std::string dir;  // DIR/approaches/<name>/<experiment>/frames.csv; DIR/suite.md is written
  std::vector<std::string> experiments;  // in table order
  std::vector<std::string> baselines;    // paired improvements against each (e.g. naive, no_boom)
  double confidence = 0.95;
  // The integrity section's protection levels multiplied by it (IntegrityOptions): checks only.
  double protection_level_scale = 1.0;
};

struct SuiteReportResult {
  std::string path;                     // DIR/suite.md
  std::vector<std::string> approaches;  // those found, in name order
  // "<approach>/<experiment>" without a frames.csv, or with fewer rows than the approach's
  // most complete experiment or than its run.json planned: the report is then marked
  // incomplete, each with why ("not flown", "123 of 300 planned frames flown (run failed)").
  std::vector<std::string> incomplete;
  std::map<std::string, std::string> incomplete_why;
};

// DIR/suite.md: the run details (DIR/run.txt) and the approaches' settings (DIR/approaches.csv)
// if present; per region, each experiment's coverage and its average error magnitude per
// component as the mean over approaches with a confidence interval; and each experiment's
// paired per-approach improvement over each baseline (the thesis's average improvement, on the
// frames both estimated in that approach) with its interval; integrity per region summed over
// the approaches (integrity.h) with the Stanford diagrams (DIR/plots/). Throws std::runtime_error
// when no approach has results or the report cannot be written, aar_geometry::LoadError for a bad
// CSV.
SuiteReportResult WriteSuiteReport(const SuiteReportOptions& options);

}  // namespace aar_eval
