// The section of report.md and suite.md that gives coverage against what the boom left of the
// receiver in view (FrameRecord::visible_fraction); not installed.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "aar_eval/tables.h"

namespace aar_eval {

// An experiment's name and its runs' frames (one run in report.md, every approach in suite.md).
using ExperimentRuns = std::pair<std::string, std::vector<const std::vector<FrameRecord>*>>;

// "## Coverage against visibility" and its table, ending with the table's last row: per
// experiment and region, the frames estimated of those in each bin of visible fraction, summed
// over the runs. "" when no frame had its visibility measured (bags, real rigs, runs from before
// it was measured).
std::string VisibilitySection(const std::vector<ExperimentRuns>& experiments);

}  // namespace aar_eval
