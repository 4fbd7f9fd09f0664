// make_report: DIR/report.md from DIR/<experiment>/frames.csv of each experiment
// (aar_eval::WriteReport): per-region tables in the thesis's layout, % difference against the
// baseline, the headline average improvement, misses, and the plots and run details if present.
//   make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]
#include <iostream>
#include <sstream>

#include "aar_eval/report.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: make_report DIR EXPERIMENT[,EXPERIMENT...] [BASELINE]\n";
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
