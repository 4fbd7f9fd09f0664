#pragma once

#include <string>
#include <utility>
#include <vector>

namespace aar_eval {

// One suite run (scripts/run --suite's DIR) per world: the same approaches and experiments flown
// in the ideal world and with each realism effect (issue 16, scripts/run --worlds).
struct WorldsReportOptions {
  std::string path;  // the report to write (markdown)
  // (name, suite DIR) in table order; the first is the reference (the ideal world) that every
  // other world's cost is measured against.
  std::vector<std::pair<std::string, std::string>> worlds;
  std::vector<std::string> experiments;  // in table order
  double confidence = 0.95;
};

struct WorldsReportResult {
  std::string path;
  // "<world>/<approach>/<experiment>" present in the reference world but without a frames.csv
  // in this one: the report is then marked incomplete.
  std::vector<std::string> missing;
};

// Per region (A, B, C, whole approach), experiment and world: coverage and the mean over
// approaches of each approach's mean position error magnitude [m] (per frame the norm of the
// x, y, z error) and attitude error magnitude [deg] (the norm of the roll, pitch, yaw error),
// with confidence intervals; then each world's cost against the reference: per approach the
// ratio of its error to the reference world's on the same approach, and the mean ratio over
// approaches with its interval (1: no cost). Each world's run details (DIR/run.txt) are quoted.
// Throws std::invalid_argument for fewer than two worlds or no experiments,
// std::runtime_error when the reference has no results or the report cannot be written, and
// aar_geometry::LoadError for a bad frames.csv.
WorldsReportResult WriteWorldsReport(const WorldsReportOptions& options);

}  // namespace aar_eval
