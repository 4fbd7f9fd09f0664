#include "aar_eval/suite.h"

#include <gtest/gtest.h>

#include <cmath>
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

// Values checked by hand: mean 2, sample sd 1, n = 3: t(0.975, 2) = 4.302653 and the half
// width 4.302653 / sqrt(3) = 2.484138.
TEST(Suite, MeanIntervalByHand) {
  const Interval i = MeanInterval({1.0, 2.0, 3.0, std::nan("")});
  EXPECT_EQ(i.n, 3);
  EXPECT_DOUBLE_EQ(i.mean, 2.0);
  EXPECT_NEAR(i.high - i.mean, 2.484138, 1e-6);
  EXPECT_NEAR(i.mean - i.low, 2.484138, 1e-6);
  const Interval one = MeanInterval({5.0});
  EXPECT_EQ(one.n, 1);
  EXPECT_EQ(one.low, 5.0);
  EXPECT_EQ(one.high, 5.0);
  EXPECT_EQ(MeanInterval({}).n, 0);
  EXPECT_THROW(MeanInterval({1.0, 2.0}, 1.5), std::invalid_argument);
}

FrameRecord Frame(double t, double range_m, double x_error, bool estimated = true) {
  FrameRecord f;
  f.t = t;
  f.range_m = range_m;
  f.region = aar_geometry::RegionOfRange(range_m);
  f.estimated = estimated;
  f.error = {x_error, 0.1, 0.1, 1.0, 1.0, 1.0};
  f.published = estimated;
  f.published_error = f.error;
  return f;
}

// Three approaches: dynamic halves naive's x error on every frame in region C, and misses one
// region B frame of approach 2; approach 3 has no dynamic run, and approach 1's naive run
// planned 5 frames and failed after 3 (both incomplete, named with why).
TEST(Suite, MeansIntervalsPairedGainsAndIncompleteRuns) {
  const std::string dir = testing::TempDir() + "/aar_eval_suite_test";
  std::filesystem::remove_all(dir);
  for (int a = 1; a <= 3; ++a) {
    const std::string approach = dir + "/approaches/0" + std::to_string(a);
    std::filesystem::create_directories(approach + "/naive");
    const double x = 0.1 * a;  // naive's x error: 0.1, 0.2, 0.3
    WriteFrameCsv(approach + "/naive/frames.csv",
                  {Frame(1.0, 100.0, 1.0), Frame(2.0, 50.0, 1.0), Frame(3.0, 35.0, x)});
    if (a == 3) {  // and a frame at 200 m: outside the regions, said under the coverage table
      WriteFrameCsv(approach + "/naive/frames.csv", {Frame(1.0, 100.0, 1.0), Frame(2.0, 50.0, 1.0),
                                                     Frame(3.0, 35.0, x), Frame(4.0, 200.0, x)});
      continue;
    }
    std::filesystem::create_directories(approach + "/dynamic");
    WriteFrameCsv(approach + "/dynamic/frames.csv",
                  {Frame(1.0, 100.0, 1.0), Frame(2.0, 50.0, 1.0, a != 2), Frame(3.0, 35.0, x / 2)});
  }
  std::ofstream(dir + "/approaches.csv") << "name,seed\n01,1\n02,2\n03,3\n";
  std::ofstream(dir + "/approaches/01/naive/run.json") << R"({"status": "failed", "frames": 5})";
  SuiteReportOptions options;
  options.dir = dir;
  options.experiments = {"naive", "dynamic"};
  options.baselines = {"naive"};
  const SuiteReportResult r = WriteSuiteReport(options);
  EXPECT_EQ(r.approaches, (std::vector<std::string>{"01", "02", "03"}));
  EXPECT_EQ(r.incomplete, (std::vector<std::string>{"01/naive", "03/dynamic"}));
  const std::string report = Read(r.path);
  EXPECT_NE(report.find("**INCOMPLETE:** missing or short: 01/naive (3 of 5 planned frames "
                        "flown (run failed)), 03/dynamic (not flown)"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| 01 | 1 |"), std::string::npos) << report;  // approaches.csv
  EXPECT_NE(report.find("\n- naive: 1 of 10 frames outside the regions (a range under 32 m or "
                        "over 175 m, or not finite), in no table\n"),
            std::string::npos)
      << report;
  // Coverage of region B: 100 % and 0 %: mean 50, interval +/- t(0.975, 1) x 50 = 635.3,
  // clipped to 0-100 %.
  EXPECT_NE(report.find("| dynamic | 2 | 100.0 [100.0, 100.0] | 50.0 [0.0, 100.0] |"),
            std::string::npos)
      << report;
  // Region C x error: naive 0.1, 0.2, 0.3 -> 0.200 [-0.048, 0.448].
  EXPECT_NE(report.find("| naive | 3 | 0.200 [-0.048, 0.448] |"), std::string::npos) << report;
  // Paired gain in region C: x 50 % in both approaches, the rest 0: 8.3 % with no spread;
  // region B has a common frame in approach 1 only.
  EXPECT_NE(report.find("| dynamic | 2 | 0.0 [0.0, 0.0] % unresolved | 0.0 (n = 1) % | "
                        "8.3 [8.3, 8.3] % better |"),
            std::string::npos)
      << report;

  // Wrong lock: naive's region B frame is 1 m off, its run lasts until the next frame (1 s, not
  // longer than 1 s) in each approach.
  EXPECT_NE(
      report.find("| naive | 3 | 0 | 1.00 [1.00, 1.00] | 1.0 (approach 01, from t = 2.0 s) |"),
      std::string::npos)
      << report;

  std::filesystem::remove_all(dir + "/approaches");
  EXPECT_THROW(WriteSuiteReport(options), std::runtime_error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aar_eval
