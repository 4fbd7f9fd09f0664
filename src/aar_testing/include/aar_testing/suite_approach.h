#pragma once

#include <string>

namespace aar_testing {

// The suite's approach of `seed` (scripts/run --suite: aar_sim::VariedApproach) for the receiver
// description `receiver` (empty: the C-12's), ending with its receptacle on the nozzle tip of the
// boom at its static pose, written to a temporary file of its own: its path (the caller removes
// it).
std::string WriteSuiteApproach(int seed, const std::string& receiver = "");

}  // namespace aar_testing
