#include "aar_eval/report.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <aar_geometry/load_error.h>

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
  f.published = estimated;
  f.published_error = f.error;
  return f;
}

// A miss that holds an earlier estimate whose error is now `x_error`.
FrameRecord Held(double t, double x_error) {
  FrameRecord f = Frame(t, 0.0, false);
  f.published = true;
  f.published_error = {x_error, 0.01, 0.01, 0.1, 0.1, 0.1};
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
  // naive misses its second frame, holding its first (x 0.5 off by then); dynamic halves the x
  // error where both estimate, and is far worse (x 2.0) on the frame naive missed.
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4), Held(1.1, 0.5)});
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2), Frame(1.1, 2.0)});
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
  // Coverage per region.
  EXPECT_NE(report.find("| naive | - | - | 1 / 2 | 1 / 2 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| dynamic | - | - | 2 / 2 | 2 / 2 |"), std::string::npos) << report;
  EXPECT_NE(report.find("Miss policy:"), std::string::npos);
  // The headline compares the frame both estimated: x 0.2 against 0.4, 50 % / 6 components.
  EXPECT_NE(report.find("- dynamic: average improvement over naive: 8.3% on the 1 frames both "
                        "estimated (dynamic estimated 2 of 2, naive 1)"),
            std::string::npos)
      << report;
  // As published: naive holds 0.5 on the second frame; dynamic (0.2 + 2.0) / 2 = 1.1 against
  // (0.4 + 0.5) / 2 = 0.45 in x: -144.4 % / 6 = -24.1 %.
  EXPECT_NE(report.find("as published (the last estimate held through misses): -24.1% on 2 "
                        "frames"),
            std::string::npos)
      << report;
  // The % row of the region table is on the same frame; dynamic's own row is over both.
  EXPECT_NE(report.find("| Region C (38-32 m) | dynamic average error magnitude | 2 (2) | 1.100 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| Region C (38-32 m) | % difference, dynamic against naive, same frames "
                        "| 1 | 50.00 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("## As published: the last estimate held through misses"),
            std::string::npos);
  EXPECT_NE(report.find("| Region C (38-32 m) | naive average error magnitude | 2 (2) | 0.450 |"),
            std::string::npos)
      << report;

  options.experiments = {"static_wings_nose"};
  EXPECT_THROW(WriteReport(options), std::runtime_error);
  std::filesystem::remove_all(dir);
}

// Every frame estimated by both: the headline says so, and no miss policy is needed.
TEST(Report, EveryFrameEstimatedIsSaidAndHasNoMissSection) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_full";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic"}) std::filesystem::create_directories(dir + "/" + e);
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4), Frame(1.1, 0.4)});
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2), Frame(1.1, 0.2)});
  const std::string report = Read(WriteReport({dir, {"naive", "dynamic"}, "naive"}).path);
  EXPECT_NE(report.find("- dynamic: average improvement over naive: 8.3% on every frame (2) "
                        "(thesis: 74.1%, on every frame)"),
            std::string::npos)
      << report;
  EXPECT_EQ(report.find("Miss policy:"), std::string::npos);
  EXPECT_EQ(report.find("## As published"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A full disk (report.md on /dev/full, which refuses every write with ENOSPC): the report was
// once a 0-byte file and exit 0, the write being buffered past the check. Now an error naming it;
// the same for frames.csv.
TEST(Report, AFullDiskIsAnErrorNotAnEmptyReport) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_full_disk";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic"}) std::filesystem::create_directories(dir + "/" + e);
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4)});
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2)});
  std::filesystem::create_symlink("/dev/full", dir + "/report.md");
  try {
    WriteReport({dir, {"naive", "dynamic"}, "naive"});
    ADD_FAILURE() << "a report written to a full disk was taken as written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("report.md: write failed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WriteFrameCsv("/dev/full", {Frame(1.0, 0.4)}), aar_geometry::LoadError);
  std::filesystem::remove_all(dir);
}

// The make_report tool, as scripts/run calls it, on hand-made CSVs whose frame sets differ
// (dynamic has a frame naive never saw, naive one dynamic missed), and on bad input.
TEST(Report, MakeReportToolOnMismatchedFrameSetsAndBadInput) {
  const std::string dir = testing::TempDir() + "/aar_eval_make_report";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic", "broken"})
    std::filesystem::create_directories(dir + "/" + e);
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4), Frame(1.1, 0.4), Held(1.2, 0.6)});
  WriteFrameCsv(dir + "/dynamic/frames.csv",
                {Frame(1.0, 0.1), Frame(1.1, 0.1, false), Frame(1.2, 0.1), Frame(1.3, 9.0)});
  auto run = [&](const std::string& args) {
    return std::system(
        (std::string(MAKE_REPORT) + " " + args + " > " + dir + "/out.txt 2>&1").c_str());
  };
  ASSERT_EQ(run(dir + " naive,dynamic,tracking naive"), 0) << Read(dir + "/out.txt");
  const std::string out = Read(dir + "/out.txt");
  EXPECT_NE(out.find("experiment 'tracking' left out"), std::string::npos) << out;
  EXPECT_NE(out.find("(2 experiments)"), std::string::npos) << out;
  const std::string report = Read(dir + "/report.md");
  // Only frame 1.0 has an estimate in both: x 0.1 against 0.4.
  EXPECT_NE(report.find("- dynamic: average improvement over naive: 12.5% on the 1 frames both "
                        "estimated (dynamic estimated 3 of 4, naive 2)"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| Region C (38-32 m) | % difference, dynamic against naive, same frames "
                        "| 1 | 75.00 |"),
            std::string::npos)
      << report;

  std::ofstream(dir + "/broken/frames.csv") << FrameCsvHeader() << "\n0,36,C,1\n";
  EXPECT_NE(run(dir + " naive,broken naive"), 0);
  EXPECT_NE(Read(dir + "/out.txt").find("broken/frames.csv: line 2: 4 cells, 23 expected"),
            std::string::npos)
      << Read(dir + "/out.txt");
  EXPECT_NE(run(dir + " nothing"), 0);
  EXPECT_NE(Read(dir + "/out.txt").find("no experiment has results"), std::string::npos);
  EXPECT_EQ(run(dir), 2 << 8);  // usage
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aar_eval
