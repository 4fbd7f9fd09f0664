#include "aar_eval/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "aar_eval/tables.h"

namespace aar_eval {
namespace {

FrameRecord Frame(double t, double x_error, bool estimated = true) {
  FrameRecord f;
  f.t = t;
  f.range_m = 36.0;
  f.region = aar_geometry::Region::kC;
  f.estimated = estimated;
  f.error = {x_error, 0.01, 0.01, 0.1, 0.1, 0.1};
  return f;
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Report, TablesHeadlineAndMissingExperiments) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_test";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic"}) std::filesystem::create_directories(dir + "/" + e);
  // naive misses its second frame; dynamic halves the x error.
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4), Frame(1.1, 0.4, false)});
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2), Frame(1.1, 0.2)});
  std::ofstream(dir + "/run.txt") << "commit: abc1234\n";

  ReportOptions options;
  options.dir = dir;
  options.experiments = {"dynamic", "static_wings_nose", "naive"};
  options.baseline = "naive";
  const ReportResult r = WriteReport(options);
  EXPECT_EQ(r.path, dir + "/report.md");
  EXPECT_EQ(r.experiments, (std::vector<std::string>{"naive", "dynamic"}));  // baseline first
  EXPECT_EQ(r.missing, (std::vector<std::string>{"static_wings_nose"}));
  const std::string report = Read(r.path);
  EXPECT_NE(report.find("commit: abc1234"), std::string::npos);
  EXPECT_NE(report.find("## Headline"), std::string::npos);
  // Over all frames the averages differ in frame sets: said, and compared on the common one.
  EXPECT_NE(report.find("over different frames: dynamic estimated 2 of 2, naive 1 of 2"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("on the 1 frames both estimated: 8.3%"), std::string::npos) << report;
  EXPECT_NE(report.find("## Average error magnitude"), std::string::npos);
  EXPECT_NE(report.find("## RMS error"), std::string::npos);

  options.experiments = {"static_wings_nose"};
  EXPECT_THROW(WriteReport(options), std::runtime_error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aar_eval
