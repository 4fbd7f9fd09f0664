#include "aar_eval/worlds.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "aar_eval/tables.h"

namespace aar_eval {
namespace {

std::string Read(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A frame whose position error is (3 s, 4 s, 0) m (norm 5 s) and attitude error (0, 0, s) deg.
FrameRecord Frame(double t, double range_m, double s, bool estimated = true) {
  FrameRecord f;
  f.t = t;
  f.range_m = range_m;
  f.region = aar_geometry::RegionOfRange(range_m);
  f.estimated = estimated;
  f.error = {3.0 * s, 4.0 * s, 0.0, 0.0, 0.0, s};
  f.published = estimated;
  f.published_error = f.error;
  return f;
}

void Write(const std::string& dir, const std::string& approach, const std::string& experiment,
           const std::vector<FrameRecord>& frames) {
  const std::string d = dir + "/approaches/" + approach + "/" + experiment;
  std::filesystem::create_directories(d);
  WriteFrameCsv(d + "/frames.csv", frames);
}

// Ideal: region C errors of 0.1 (approach 01) and 0.2 (02). Turbulence doubles approach 01's and
// triples approach 02's, and misses one of approach 02's two region C frames; the sun world has
// no approach 02 (missing).
TEST(Worlds, ErrorsCostsCoverageAndMissingRuns) {
  const std::string root = testing::TempDir() + "/aar_eval_worlds_test";
  std::filesystem::remove_all(root);
  const std::string ideal = root + "/ideal", turb = root + "/turbulence", sun = root + "/sun";
  for (const auto& [a, s] : std::vector<std::pair<std::string, double>>{{"01", 0.1}, {"02", 0.2}}) {
    Write(ideal, a, "dynamic", {Frame(1.0, 100.0, 1.0), Frame(2.0, 35.0, s), Frame(3.0, 34.0, s)});
    const double k = a == "01" ? 2.0 : 3.0;
    Write(turb, a, "dynamic",
          {Frame(1.0, 100.0, 1.0), Frame(2.0, 35.0, k * s), Frame(3.0, 34.0, k * s, a == "01")});
  }
  Write(sun, "01", "dynamic",
        {Frame(1.0, 100.0, 1.0), Frame(2.0, 35.0, 0.1), Frame(3.0, 34.0, 0.1)});
  std::filesystem::create_directories(ideal);
  std::ofstream(ideal + "/run.txt")
      << "command: scripts/run --suite 2 --worlds ideal,turbulence,sun\n";

  WorldsReportOptions options;
  options.path = root + "/worlds.md";
  options.worlds = {{"ideal", ideal}, {"turbulence", turb}, {"sun", sun}};
  options.experiments = {"dynamic"};
  const WorldsReportResult r = WriteWorldsReport(options);
  EXPECT_EQ(r.missing, (std::vector<std::string>{"sun/02/dynamic"}));
  const std::string report = Read(r.path);
  EXPECT_NE(report.find("**INCOMPLETE:** missing: sun/02/dynamic"), std::string::npos) << report;
  EXPECT_NE(report.find("command: scripts/run --suite 2 --worlds ideal,turbulence,sun"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("(no run.txt)"), std::string::npos) << report;
  const std::string region_c = report.substr(report.find("## Region C"));
  // Ideal: position 0.5 and 1.0 m -> mean 0.750, +/- t(0.975, 1) x 0.25 = 3.177; attitude 0.1
  // and 0.2 deg.
  EXPECT_NE(region_c.find("| dynamic | ideal | 2 | 100.0 [100.0, 100.0] | 0.750 [-2.427, 3.927] | "
                          "0.150 [-0.485, 0.785] | - | - |"),
            std::string::npos)
      << region_c;
  // Turbulence: coverage 100 and 50 % (the interval clipped to 0-100), position 1.0 and 3.0 m,
  // costs 2 and 3 -> 2.50.
  EXPECT_NE(region_c.find("| dynamic | turbulence | 2 | 75.0 [0.0, 100.0] | 2.000 [-10.706, "
                          "14.706] | 0.400 [-2.141, 2.941] | 2.50 [-3.85, 8.85] | 2.50 [-3.85, "
                          "8.85] |"),
            std::string::npos)
      << region_c;
  EXPECT_NE(region_c.find("| dynamic | sun | 1 | 100.0 (n = 1) | 0.500 (n = 1) | 0.100 (n = 1) | "
                          "1.00 (n = 1) | 1.00 (n = 1) |"),
            std::string::npos)
      << region_c;

  options.worlds.pop_back();
  options.worlds.pop_back();
  EXPECT_THROW(WriteWorldsReport(options), std::invalid_argument);
  options.worlds = {{"empty", root + "/nothing"}, {"turbulence", turb}};
  EXPECT_THROW(WriteWorldsReport(options), std::runtime_error);
  std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace aar_eval
