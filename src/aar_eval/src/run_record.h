// What the campaign driver recorded about a run (DIR/run.json), as the report writers
// (report.cpp, suite.cpp) need it to count against the plan; not installed.
#pragma once

#include <string>

namespace aar_eval {

// The run planned in `run_dir`/run.json: "frames" (0 when there is no record) and "status"
// ("ok", "failed", "interrupted"; empty when there is no record).
struct PlannedRun {
  int frames = 0;
  std::string status;
};
PlannedRun ReadPlannedRun(const std::string& run_dir);

// "N of M planned frames flown (run STATUS)" of a run that flew `flown` frames, or "" when it
// flew all it planned (or nothing was planned).
std::string ShortOfPlan(const PlannedRun& planned, size_t flown);

}  // namespace aar_eval
