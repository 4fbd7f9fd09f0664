// make_report: DIR/report.md from DIR/<experiment>/frames.csv of each experiment
// (aar_eval::WriteReport): per-region tables in the thesis's layout, % difference against the
// baseline, the headline average improvement, misses, and the plots and run details if present.
// With --suite: DIR/suite.md from DIR/approaches/*/<experiment>/frames.csv (aar_eval::
// WriteSuiteReport): means over approaches with 95 % intervals, paired improvements.
// With --worlds: OUT from the suite DIRs of several worlds (aar_eval::WriteWorldsReport): each
// realism effect's cost against the first world (scripts/run --worlds).
// --protection-level-scale F (report and suite): the integrity section's protection levels
// multiplied by F before they are compared, to check that its counts can fail; the report says so.
//   make_report [--protection-level-scale F] DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]
//   make_report [--protection-level-scale F] --suite DIR EXPERIMENT[,EXPERIMENT...]
//               BASELINE[,BASELINE...]
//   make_report --worlds OUT EXPERIMENT[,EXPERIMENT...] NAME=DIR,NAME=DIR[,...]
#include <cmath>
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

constexpr const char* kScaleUsage =
    "  --protection-level-scale F: the integrity section's protection levels multiplied by F "
    "(> 0; default 1) before they are counted, a check that its counts can fail\n";

int Suite(int argc, char** argv, double scale) {
  if (argc != 5) {
    std::cerr << "usage: make_report [--protection-level-scale F] --suite DIR "
                 "EXPERIMENT[,EXPERIMENT...] BASELINE[,BASELINE...]\n"
              << kScaleUsage;
    return 2;
  }
  aar_eval::SuiteReportOptions options;
  options.protection_level_scale = scale;
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

// F of a leading --protection-level-scale F, taken out of argv; 1 without one; NaN when F is no
// number above 0.
double TakeScale(int& argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) != "--protection-level-scale") return 1.0;
  double scale = std::nan("");
  if (argc > 2) {
    try {
      size_t used = 0;
      const std::string text = argv[2];
      const double v = std::stod(text, &used);
      if (used == text.size() && std::isfinite(v) && v > 0.0) scale = v;
    } catch (const std::exception&) {
    }
  }
  const int taken = argc > 2 ? 2 : 1;
  for (int i = 1; i + taken < argc; ++i) argv[i] = argv[i + taken];
  argc -= taken;
  return scale;
}

}  // namespace

int main(int argc, char** argv) {
  const double scale = TakeScale(argc, argv);
  const bool worlds = argc > 1 && std::string(argv[1]) == "--worlds";
  if (std::isnan(scale) || (scale != 1.0 && worlds)) {
    std::cerr << "make_report: --protection-level-scale needs a number above 0, before DIR or "
                 "--suite (not with --worlds)\n"
              << kScaleUsage;
    return 2;
  }
  if (argc > 1 && std::string(argv[1]) == "--suite") return Suite(argc, argv, scale);
  if (worlds) return Worlds(argc, argv);
  if (argc < 3) {
    std::cerr << "usage: make_report [--protection-level-scale F] DIR EXPERIMENT[,EXPERIMENT...] "
                 "[BASELINE]\n"
                 "       make_report [--protection-level-scale F] --suite DIR "
                 "EXPERIMENT[,EXPERIMENT...] BASELINE[,BASELINE...]\n"
              << "       " << std::string(kWorldsUsage).substr(7) << kScaleUsage;
    return 2;
  }
  aar_eval::ReportOptions options;
  options.protection_level_scale = scale;
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
