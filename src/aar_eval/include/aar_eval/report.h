#pragma once

#include <string>
#include <vector>

namespace aar_eval {

struct ReportOptions {
  std::string dir;                       // holds <experiment>/frames.csv; report.md goes here
  std::vector<std::string> experiments;  // in table order
  std::string baseline;                  // % differences against it; empty: none
  // The integrity section's protection levels multiplied by it (IntegrityOptions): checks only.
  double protection_level_scale = 1.0;
};

struct ReportResult {
  std::string path;                      // DIR/report.md
  std::vector<std::string> experiments;  // those with results, baseline first
  std::vector<std::string> missing;      // asked for, without DIR/<experiment>/frames.csv
};

// DIR/report.md: the run details (DIR/run.txt), the headline average improvement over the
// baseline (and on the frames both estimated, when they differ), per-region tables in the
// thesis's layout (average error magnitude and RMS, % difference), integrity per region (NEES,
// misleading and hazardously misleading frames, availability; integrity.h) with the Stanford
// diagrams, the error-against-range plots (DIR/plots/) and rviz captures (DIR/captures/) that
// exist. Throws std::runtime_error when no
// experiment has results or the report cannot be written, aar_geometry::LoadError for a bad CSV.
ReportResult WriteReport(const ReportOptions& options);

}  // namespace aar_eval
