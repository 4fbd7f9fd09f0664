#include "aar_eval/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

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

// Coverage against the plan (issue 46): frames outside the regions were left out of every table
// without a word, and a failed run's coverage counted only the frames it flew ("123 / 123" of a
// 300-frame plan). Now each gets a line under the coverage table.
TEST(Report, FramesOutsideTheRegionsAndAShortRunAreNamed) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_plan";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic"}) std::filesystem::create_directories(dir + "/" + e);
  FrameRecord far = Frame(0.9, 0.3);
  far.range_m = 235.0;
  far.region = aar_geometry::Region::kOutside;
  WriteFrameCsv(dir + "/naive/frames.csv", {far, Frame(1.0, 0.4), Frame(1.1, 0.4)});
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2)});
  std::ofstream(dir + "/naive/run.json") << "{\"status\": \"ok\", \"frames\": 3}";
  std::ofstream(dir + "/dynamic/run.json") << "{\n \"status\": \"failed\",\n \"frames\": 3,\n}";
  const std::string report = Read(WriteReport({dir, {"naive", "dynamic"}, "naive"}).path);
  EXPECT_NE(report.find("- naive: 1 of 3 frames outside the regions (a range under 32 m or over "
                        "175 m, or not finite), in no table"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("- **dynamic: 1 of 3 planned frames flown (run failed)** (why: the Run "
                        "section); its tables cover only those"),
            std::string::npos)
      << report;
  EXPECT_EQ(report.find("naive: 3 of 3 planned"), std::string::npos) << report;
  std::filesystem::remove_all(dir);
}

// Coverage against visibility (issue 44): frames binned by the visible share of the receiver,
// per region; a run without any measured frame has no such section.
TEST(Report, CoverageAgainstVisibilityPerRegionAndBin) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_visibility";
  std::filesystem::remove_all(dir);
  for (const char* e : {"naive", "dynamic"}) std::filesystem::create_directories(dir + "/" + e);
  std::vector<FrameRecord> frames = {Frame(1.0, 0.4), Frame(1.1, 0.4, false),
                                     Frame(1.2, 0.4, false), Frame(1.3, 0.4), Frame(1.4, 0.4)};
  const double fractions[] = {0.1, 0.3, 0.8, 1.0, std::nan("")};
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i].visible_fraction = fractions[i];
    frames[i].visible_px = std::isnan(fractions[i]) ? 0.0 : 500.0 * fractions[i];
    frames[i].visible_fraction_least = fractions[i] / 4.0;  // the other camera sees less
  }
  frames[4].region = aar_geometry::Region::kA;
  frames[4].range_m = 150.0;
  WriteFrameCsv(dir + "/naive/frames.csv", frames);
  WriteFrameCsv(dir + "/dynamic/frames.csv", {Frame(1.0, 0.2)});  // not measured
  const std::string report = Read(WriteReport({dir, {"naive", "dynamic"}, "naive"}).path);
  EXPECT_NE(report.find("| experiment | region | 0-25 % | 25-50 % | 50-75 % | 75-90 % | >= 90 % | "
                        "in no view |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| naive | A | - | - | - | - | - | 1 / 1 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| naive | C | 1 / 1 | 0 / 1 | - | 0 / 1 | 1 / 1 | - |"), std::string::npos)
      << report;
  EXPECT_NE(report.find("| naive | all | 1 / 1 | 0 / 1 | - | 0 / 1 | 1 / 1 | 1 / 1 |"),
            std::string::npos)
      << report;
  // By the camera that saw least (a quarter of the other's share): 0.025 .. 0.25.
  EXPECT_NE(report.find("| naive | C | 1 / 3 | 1 / 1 | - | - | - | - |"), std::string::npos)
      << report;
  EXPECT_EQ(report.find("| dynamic | C |"), std::string::npos) << report;
  // Frames of the format before the least view: the first table, not the second.
  for (FrameRecord& f : frames) f.visible_fraction_least = std::nan("");
  WriteFrameCsv(dir + "/naive/frames.csv", frames);
  const std::string older = Read(WriteReport({dir, {"naive", "dynamic"}, "naive"}).path);
  EXPECT_NE(older.find("| naive | C | 1 / 1 | 0 / 1 | - | 0 / 1 | 1 / 1 | - |"), std::string::npos)
      << older;
  EXPECT_EQ(older.find("camera that saw least"), std::string::npos) << older;
  WriteFrameCsv(dir + "/naive/frames.csv", {Frame(1.0, 0.4)});
  EXPECT_EQ(Read(WriteReport({dir, {"naive", "dynamic"}, "naive"}).path).find("visibility"),
            std::string::npos);
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
  EXPECT_NE(Read(dir + "/out.txt").find("broken/frames.csv: line 2: 4 cells, 31 expected"),
            std::string::npos)
      << Read(dir + "/out.txt");
  EXPECT_NE(run(dir + " nothing"), 0);
  EXPECT_NE(Read(dir + "/out.txt").find("no experiment has results"), std::string::npos);
  EXPECT_EQ(run(dir), 2 << 8);  // usage
  std::filesystem::remove_all(dir);
}

// `f` with protection levels (m, deg), the alert limits 1 m and 2 deg, and a NEES.
FrameRecord WithLevels(FrameRecord f, double pl_m, double pl_deg, double nees) {
  f.pl_position_m = pl_m;
  f.pl_attitude_deg = pl_deg;
  f.al_position_m = 1.0;
  f.al_attitude_deg = 2.0;
  f.nees = nees;
  return f;
}

// flight: a nominal frame, one 2 m off whose 5 m level is above the 1 m limit (bounded, not
// available, not in alert), and a miss; naive has no levels (a publisher without integrity).
// With the levels scaled down to 1 %, both estimates are available and misleading, and the 2 m
// one hazardously so: the counts that are 0 at scale 1 can fail.
TEST(Report, IntegritySectionAndScaledLevelsCanFail) {
  const std::string dir = testing::TempDir() + "/aar_eval_report_integrity";
  std::filesystem::remove_all(dir);
  const std::vector<FrameRecord> flight = {WithLevels(Frame(1.0, 0.1), 0.5, 1.0, 5.0),
                                           WithLevels(Frame(1.1, 2.0), 5.0, 1.0, 30.0),
                                           Frame(1.2, 0.0, false)};
  for (const std::string& d : {dir, dir + "/suite/approaches/01", dir + "/suite/approaches/02"}) {
    std::filesystem::create_directories(d + "/flight");
    std::filesystem::create_directories(d + "/naive");
    WriteFrameCsv(d + "/flight/frames.csv", flight);
    WriteFrameCsv(d + "/naive/frames.csv", {Frame(1.0, 0.4)});
  }
  std::filesystem::create_directories(dir + "/plots");
  std::ofstream(dir + "/plots/flight_stanford.png") << "png";
  const std::string report = Read(WriteReport({dir, {"naive", "flight"}, "naive"}).path);
  const size_t section = report.find("## Integrity");
  ASSERT_NE(section, std::string::npos) << report;
  EXPECT_GT(section, report.find("## RMS error"));  // after the error tables
  EXPECT_NE(report.find("| experiment | region | estimated / frames | NEES mean | beyond 99.9 % "
                        "(%) | misleading | HMI | availability (%) |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| naive | region C | 1 / 1 | - | - | - | - | - |"), std::string::npos)
      << report;
  EXPECT_NE(report.find("| flight | region C | 2 / 3 | 17.50 | 50.0 | 0 | 0 | 33.3 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| flight | whole approach | 2 / 3 | 17.50 | 50.0 | 0 | 0 | 33.3 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("22.458"), std::string::npos);
  EXPECT_NE(report.find("![flight Stanford diagram](plots/flight_stanford.png)"),
            std::string::npos);
  EXPECT_EQ(report.find("scaled by"), std::string::npos);

  // The same through make_report, the levels scaled to 1 %: the report and the suite.
  auto run = [&](const std::string& args) {
    return std::system(
        (std::string(MAKE_REPORT) + " " + args + " > " + dir + "/out.txt 2>&1").c_str());
  };
  ASSERT_EQ(run("--protection-level-scale 0.01 " + dir + " naive,flight naive"), 0)
      << Read(dir + "/out.txt");
  const std::string scaled = Read(dir + "/report.md");
  EXPECT_NE(scaled.find("| flight | region C | 2 / 3 | 17.50 | 50.0 | 2 | 1 | 66.7 |"),
            std::string::npos)
      << scaled;
  EXPECT_NE(scaled.find("**Protection levels scaled by 0.01**"), std::string::npos);
  ASSERT_EQ(run("--suite " + dir + "/suite naive,flight naive"), 0) << Read(dir + "/out.txt");
  EXPECT_NE(Read(dir + "/suite/suite.md")
                .find("| flight | region C | 4 / 6 | 17.50 | 50.0 | 0 | 0 | 33.3 |"),
            std::string::npos)
      << Read(dir + "/suite/suite.md");
  ASSERT_EQ(run("--protection-level-scale 0.01 --suite " + dir + "/suite naive,flight naive"), 0)
      << Read(dir + "/out.txt");
  EXPECT_NE(Read(dir + "/suite/suite.md")
                .find("| flight | region C | 4 / 6 | 17.50 | 50.0 | 4 | 2 | 66.7 |"),
            std::string::npos)
      << Read(dir + "/suite/suite.md");
  // A scale that is no number above 0 is a usage error.
  for (const char* bad : {"0", "-1", "abc", "nan", ""})
    EXPECT_EQ(run(std::string("--protection-level-scale ") + bad + " " + dir + " naive"), 2 << 8)
        << bad;
  EXPECT_NE(Read(dir + "/out.txt").find("--protection-level-scale F"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aar_eval
