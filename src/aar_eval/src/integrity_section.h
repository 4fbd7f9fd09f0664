// The "## Integrity" section report.md and suite.md share (report.cpp, suite.cpp); not installed.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "aar_eval/integrity.h"

namespace aar_eval {

// "## Integrity": what each column means, then one row per experiment of `order` (those in
// `stats`, [experiment][region key]) and region (A, B, C, whole approach, those with frames), and
// the Stanford diagrams DIR/plots/<experiment>_stanford.png that exist. `summed`: a sentence on
// how the figures were combined (suite.md), or empty.
void WriteIntegritySection(
    std::ostream& out, const std::vector<std::string>& order,
    const std::map<std::string, std::map<std::string, IntegrityStats>>& stats,
    const IntegrityOptions& options, const std::string& dir, const std::string& summed = "");

}  // namespace aar_eval
