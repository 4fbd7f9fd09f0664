// make_report: DIR/report.md from DIR/<experiment>/frames.csv of each experiment
// (aar_eval::WriteReport): per-region tables in the thesis's layout, % difference against the
// baseline, the headline average improvement, misses, and the plots and run details if present.
// With --suite: DIR/suite.md from DIR/approaches/*/<experiment>/frames.csv (aar_eval::
// WriteSuiteReport): means over approaches with 95 % intervals, paired improvements.
// With --worlds: OUT from the suite DIRs of several worlds (aar_eval::WriteWorldsReport): each
// realism effect's cost against the first world (scripts/realism).
//   make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]
//   make_report --suite DIR EXPERIMENT[,EXPERIMENT...] BASELINE[,BASELINE...]
//   make_report --worlds OUT EXPERIMENT[,EXPERIMENT...] NAME=DIR,NAME=DIR[,...]
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "aar_eval/report.h"
#include "aar_eval/suite.h"
#include "aar_eval/worlds.h"

namespace {

std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream s(list);
  for (std::string e; std::getline(s, e, ',');)
    if (!e.empty()) out.push_back(e);
  return out;
}

int Suite(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: make_report --suite DIR EXPERIMENT[,EXPERIMENT...] "
                 "BASELINE[,BASELINE...]\n";
    return 2;
  }
  aar_eval::SuiteReportOptions options;
  options.dir = argv[2];
  options.experiments = Split(argv[3]);
  options.baselines = Split(argv[4]);
  try {
    const auto result = aar_eval::WriteSuiteReport(options);
    for (const auto& i : result.incomplete)
      std::cerr << "make_report: " << options.dir << "/approaches/" << i
                << ": results missing or short (the report says so)\n";
    std::cout << "make_report: wrote " << result.path << " (" << result.approaches.size()
              << " approaches)\n";
  } catch (const std::exception& e) {
    std::cerr << "make_report: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

constexpr const char* kWorldsUsage =
    "usage: make_report --worlds OUT EXPERIMENT[,EXPERIMENT...] NAME=DIR,NAME=DIR[,...]\n";

int Worlds(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << kWorldsUsage;
    return 2;
  }
  aar_eval::WorldsReportOptions options;
  options.path = argv[2];
  options.experiments = Split(argv[3]);
  for (const auto& world : Split(argv[4])) {
    const size_t eq = world.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == world.size()) {
      std::cerr << "make_report: world '" << world << "' is not NAME=DIR\n" << kWorldsUsage;
      return 2;
    }
    options.worlds.emplace_back(world.substr(0, eq), world.substr(eq + 1));
  }
  try {
    const auto result = aar_eval::WriteWorldsReport(options);
    for (const auto& m : result.missing)
      std::cerr << "make_report: " << m << ": results missing (the report says so)\n";
    std::cout << "make_report: wrote " << result.path << " (" << options.worlds.size()
              << " worlds)\n";
  } catch (const std::invalid_argument& e) {
    std::cerr << "make_report: " << e.what() << "\n" << kWorldsUsage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "make_report: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--suite") return Suite(argc, argv);
  if (argc > 1 && std::string(argv[1]) == "--worlds") return Worlds(argc, argv);
  if (argc < 3) {
    std::cerr << "usage: make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]\n"
                 "       make_report --suite DIR EXPERIMENT[,EXPERIMENT...] "
                 "BASELINE[,BASELINE...]\n"
              << "       " << std::string(kWorldsUsage).substr(7);
    return 2;
  }
  aar_eval::ReportOptions options;
  options.dir = argv[1];
  std::stringstream list(argv[2]);
  for (std::string e; std::getline(list, e, ',');) options.experiments.push_back(e);
  options.baseline = argc > 3 ? argv[3] : "";
  try {
    const aar_eval::ReportResult result = aar_eval::WriteReport(options);
    for (const auto& e : result.missing) {
      std::cerr << "make_report: " << options.dir << "/" << e
                << "/frames.csv is missing: experiment '" << e << "' left out\n";
    }
    std::cout << "make_report: wrote " << result.path << " (" << result.experiments.size()
              << " experiments)\n";
  } catch (const std::exception& e) {
    std::cerr << "make_report: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
