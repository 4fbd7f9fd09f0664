#include "run_record.h"

#include <fstream>
#include <iterator>
#include <regex>

namespace aar_eval {

PlannedRun ReadPlannedRun(const std::string& run_dir) {
  std::ifstream in(run_dir + "/run.json");
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  PlannedRun run;
  std::smatch m;
  if (std::regex_search(json, m, std::regex(R"re("frames":\s*([0-9]+))re")))
    run.frames = std::stoi(m[1]);
  if (std::regex_search(json, m, std::regex(R"re("status":\s*"([a-z]+)")re"))) run.status = m[1];
  return run;
}

std::string ShortOfPlan(const PlannedRun& planned, size_t flown) {
  if (planned.frames <= static_cast<int>(flown)) return "";
  return std::to_string(flown) + " of " + std::to_string(planned.frames) +
         " planned frames flown (run " + (planned.status.empty() ? "unfinished" : planned.status) +
         ")";
}

}  // namespace aar_eval
