#include "aar_eval/tables.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <aar_geometry/load_error.h>

namespace aar_eval {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = std::filesystem::temp_directory_path().string() + "/aar_eval_" + name;
  std::ofstream(path) << text;
  return path;
}

// The frames written to DIR/aar_eval_NAME and read back; the path in `path`.
std::vector<FrameRecord> RoundTrip(const std::string& name, const std::vector<FrameRecord>& frames,
                                   std::string* path) {
  *path = std::filesystem::temp_directory_path().string() + "/aar_eval_" + name;
  WriteFrameCsv(*path, frames);
  return ReadFrameCsv(*path);
}

// Hand-made: region A has two estimates (x = 1 and -3; yaw = 2 and 2) and one miss, region B one
// estimate (x = 0.5), and a frame at 20 m is outside every region.
const char kCsv[] =
    "t,range_m,region,estimated,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,converged,iterations,rms_m,"
    "registration_ms\n"
    "0,150,A,1,1,0,0,0,0,2,1,12,0.01,5\n"
    "1,120,A,1,-3,0,0,0,0,2,0,30,0.02,6\n"
    "2,100,A,0,nan,nan,nan,nan,nan,nan,0,0,0,0\n"
    "3,50,B,1,0.5,0,0,0,0,0,1,8,0.01,4\n"
    "4,20,outside,1,9,9,9,9,9,9,1,8,0.01,4\n";

TEST(Tables, RegionStatsByHand) {
  const auto frames = ReadFrameCsv(Write("hand.csv", kCsv));
  ASSERT_EQ(frames.size(), 5u);
  const auto stats = ComputeRegionStats(frames);
  ASSERT_EQ(stats.count("C"), 0u);
  const RegionStats& a = stats.at("A");
  EXPECT_EQ(a.frames, 3);
  EXPECT_EQ(a.estimated, 2);
  EXPECT_DOUBLE_EQ(a.mean_abs[0], 2.0);        // (|1| + |-3|) / 2
  EXPECT_DOUBLE_EQ(a.rms[0], std::sqrt(5.0));  // sqrt((1 + 9) / 2)
  EXPECT_DOUBLE_EQ(a.mean_abs[5], 2.0);
  EXPECT_DOUBLE_EQ(a.rms[5], 2.0);
  const RegionStats& all = stats.at("all");  // A and B, not the 20 m frame
  EXPECT_EQ(all.frames, 4);
  EXPECT_EQ(all.estimated, 3);
  EXPECT_DOUBLE_EQ(all.mean_abs[0], 4.5 / 3.0);  // (1 + 3 + 0.5) / 3
  EXPECT_DOUBLE_EQ(all.rms[0], std::sqrt(10.25 / 3.0));
}

// Regions B and C at 10 Hz: 0.6 m off for 3 frames, a miss, 3 deg off for 12 frames to the end of
// the path; region A's error never counts.
TEST(Tables, LongestWrongLockEndsAtAMissAndAtThePathsEnd) {
  std::vector<FrameRecord> frames;
  auto add = [&](aar_geometry::Region region, bool estimated, double x, double yaw) {
    FrameRecord f;
    f.t = 0.1 * static_cast<double>(frames.size());
    f.region = region;
    f.estimated = estimated;
    f.error = {x, 0.0, 0.0, 0.0, 0.0, yaw};
    frames.push_back(f);
  };
  for (int i = 0; i < 20; ++i) add(aar_geometry::Region::kA, true, 5.0, 10.0);
  for (int i = 0; i < 3; ++i) add(aar_geometry::Region::kB, true, 0.6, 0.0);
  add(aar_geometry::Region::kB, false, 0.0, 0.0);
  add(aar_geometry::Region::kB, true, 0.4, 1.9);  // within both bounds
  for (int i = 0; i < 12; ++i) add(aar_geometry::Region::kC, true, 0.0, -3.0);
  const WrongLock lock = LongestWrongLock(frames);
  EXPECT_EQ(lock.frames, 12);
  EXPECT_NEAR(lock.seconds, 1.2, 1e-9);
  EXPECT_NEAR(lock.start_t, 2.5, 1e-9);
  EXPECT_EQ(LongestWrongLock(frames, 0.5, 5.0).frames, 3);  // only the 0.6 m run is left
  EXPECT_NEAR(LongestWrongLock(frames, 0.5, 5.0).seconds, 0.3, 1e-9);
  EXPECT_EQ(LongestWrongLock({}).frames, 0);
}

TEST(Tables, PercentDifferenceAndHeadline) {
  EXPECT_DOUBLE_EQ(PercentDifference(2.0, 8.0), 75.0);  // thesis: positive is better
  EXPECT_DOUBLE_EQ(PercentDifference(8.198, 1.125), (1.125 - 8.198) / 1.125 * 100.0);
  EXPECT_TRUE(std::isnan(PercentDifference(1.0, 0.0)));
  RegionStats value, baseline;
  value.mean_abs = {1, 1, 1, 1, 1, 1};
  baseline.mean_abs = {2, 4, 1, 2, 4, 1};  // 50, 75, 0, 50, 75, 0
  EXPECT_DOUBLE_EQ(AverageImprovement(value, baseline), 250.0 / 6.0);
}

TEST(Tables, MarkdownLayout) {
  const auto frames = ReadFrameCsv(Write("hand2.csv", kCsv));
  const std::map<std::string, std::vector<FrameRecord>> by = {{"naive", frames},
                                                              {"dynamic", frames}};
  const std::string table = MarkdownRegionTable(by, {"naive", "dynamic"}, "naive", false);
  EXPECT_NE(table.find("| Region A (175-70 m) | naive average error magnitude | 3 (2) | 2.000 |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| Region A (175-70 m) | % difference, dynamic against naive, same frames "
                       "| 2 | 0.00 |"),
            std::string::npos)
      << table;
  EXPECT_EQ(table.find("Region C"), std::string::npos);
}

// The % rows compare the same frames: dynamic estimates the frame naive missed (x = 10, far
// worse), which is in dynamic's own row but not in its % row.
TEST(Tables, PercentRowsCompareTheSameFrames) {
  const auto naive = ReadFrameCsv(Write("hand4.csv", kCsv));
  auto dynamic = naive;
  for (auto& f : dynamic) f.error[0] *= 0.5;  // half of naive's x error where both estimated
  dynamic[2].estimated = true;
  dynamic[2].error = {10, 0, 0, 0, 0, 0};
  const std::map<std::string, std::vector<FrameRecord>> by = {{"naive", naive},
                                                              {"dynamic", dynamic}};
  const std::string table = MarkdownRegionTable(by, {"naive", "dynamic"}, "naive", false);
  // Its own row: (0.5 + 1.5 + 10) / 3 = 4 over 3 frames, worse than naive's 2.
  EXPECT_NE(table.find("| Region A (175-70 m) | dynamic average error magnitude | 3 (3) | 4.000 |"),
            std::string::npos)
      << table;
  // On the 2 frames both estimated: 1 against 2, 50 % better.
  EXPECT_NE(table.find("| Region A (175-70 m) | % difference, dynamic against naive, same frames "
                       "| 2 | 50.00 |"),
            std::string::npos)
      << table;
  const auto common = CommonFrames(dynamic, naive);
  EXPECT_EQ(common.first.size(), 4u);  // the outside frame too; not the miss
  EXPECT_EQ(common.second.size(), 4u);
}

// Hold the last estimate: a miss is scored with the last estimate's error against its truth.
TEST(Tables, HoldLastPolicyScoresMissesWithThePublishedPose) {
  auto frames = ReadFrameCsv(Write("hand5.csv", kCsv));
  // The old format has no held estimates: published means estimated.
  EXPECT_FALSE(frames[2].published);
  EXPECT_TRUE(frames[1].published);
  EXPECT_EQ(frames[1].published_error, frames[1].error);
  frames[2].published = true;
  frames[2].published_error = {-4, 0, 0, 0, 0, 2};
  const auto held = ComputeRegionStats(frames, ErrorPolicy::kHoldLast);
  EXPECT_EQ(held.at("A").estimated, 3);
  EXPECT_DOUBLE_EQ(held.at("A").mean_abs[0], 8.0 / 3.0);  // (1 + 3 + 4) / 3
  EXPECT_EQ(ComputeRegionStats(frames).at("A").estimated, 2);
  const std::map<std::string, std::vector<FrameRecord>> by = {{"tracking", frames}};
  EXPECT_NE(MarkdownRegionTable(by, {"tracking"}, "", false, ErrorPolicy::kHoldLast)
                .find("| frames (published) |"),
            std::string::npos);
}

TEST(Tables, CsvRoundTripAndErrors) {
  const auto frames = ReadFrameCsv(Write("hand3.csv", kCsv));
  const std::string path = std::filesystem::temp_directory_path().string() + "/aar_eval_round.csv";
  WriteFrameCsv(path, frames);
  const auto again = ReadFrameCsv(path);
  ASSERT_EQ(again.size(), frames.size());
  EXPECT_EQ(again[1].error[0], -3.0);
  EXPECT_FALSE(again[2].estimated);
  EXPECT_EQ(again[0].track, "off");  // the old format (kCsv) reads as untracked, no NEES
  EXPECT_TRUE(std::isnan(again[0].nees));
  // The tracking columns round-trip.
  FrameRecord tracked = frames[0];
  tracked.track = "rejected";
  tracked.nees = 7.25;
  WriteFrameCsv(path, {tracked});
  EXPECT_EQ(ReadFrameCsv(path)[0].track, "rejected");
  EXPECT_EQ(ReadFrameCsv(path)[0].nees, 7.25);
  // So do the published (held) columns of a miss.
  FrameRecord miss = frames[2];
  miss.published = true;
  miss.published_error = {0.5, -0.25, 0, 1, 2, 3};
  WriteFrameCsv(path, {miss});
  EXPECT_FALSE(ReadFrameCsv(path)[0].estimated);
  EXPECT_TRUE(ReadFrameCsv(path)[0].published);
  EXPECT_EQ(ReadFrameCsv(path)[0].published_error, miss.published_error);
  // A range a hair below a region boundary keeps its region through the CSV.
  FrameRecord edge;
  edge.range_m = 38.0 - 1e-12;
  edge.region = aar_geometry::RegionOfRange(edge.range_m);
  ASSERT_EQ(edge.region, aar_geometry::Region::kC);
  WriteFrameCsv(path, {edge});
  EXPECT_EQ(ReadFrameCsv(path)[0].region, aar_geometry::Region::kC);
  auto expect = [](const std::string& text, const std::string& fragment) {
    const std::string p = Write("bad.csv", text);
    try {
      ReadFrameCsv(p);
      ADD_FAILURE() << fragment;
    } catch (const aar_geometry::LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::string header = FrameCsvHeader() + "\n";
  const std::string held = ",1,0,0,0,0,0,0,nan,nan,nan,nan,0,nan,nan,nan\n";
  expect("t,x\n", "line 1: not a frame CSV header");
  expect(header + "0,150,A,1\n", "line 2: 4 cells, 31 expected");
  expect(header + "0,150,A,1,abc,0,0,0,0,0,1,1,0,0,off,1" + held, "line 2: 'abc' is not a number");
  expect(header + "0,50,A,1,0,0,0,0,0,0,1,1,0,0,off,1" + held,
         "line 2: region 'A' does not match range 50");
  expect(header + "0,150,A,1,0,0,0,0,0,0,1,1,0,0,off,x" + held, "line 2: 'x' is not a number");
  expect(
      header +
          "0,150,A,1,0,0,0,0,0,0,1,1,0,0,off,1,0,nan,nan,nan,nan,nan,nan,1,1,1,1,0,nan,nan,nan\n",
      "line 2: estimated but not published");
  expect(header + "0,150,A,1,0,0,0,0,0,0,1,1,0,0,off,1,1,0,0,0,0,0,0,1,x,1,1,0,nan,nan,nan\n",
         "line 2: 'x' is not a number");
}

// The integrity columns round-trip; a frame without levels writes and reads NaN; the header
// before them (the published columns last) still reads, its held estimates kept.
TEST(Tables, IntegrityColumnsRoundTripAndTheOlderHeaderReads) {
  const std::string header = FrameCsvHeader();
  EXPECT_EQ(header.substr(header.find(",published_yaw_deg")),
            ",published_yaw_deg,pl_position_m,pl_attitude_deg,al_position_m,al_attitude_deg,alert,"
            "visible_fraction,visible_px,visible_fraction_least");
  FrameRecord f;
  f.t = 1.5;
  f.range_m = 36.0;
  f.region = aar_geometry::Region::kC;
  f.estimated = f.published = true;
  f.error = f.published_error = {0.5, -0.25, 0, 1, 2, 3};
  f.pl_position_m = 0.75;
  f.pl_attitude_deg = 1.125;
  f.al_position_m = 1.0;
  f.al_attitude_deg = std::numeric_limits<double>::infinity();
  f.alert = true;
  FrameRecord none = f;  // an estimate without integrity
  none.pl_position_m = none.pl_attitude_deg = none.al_position_m = none.al_attitude_deg =
      std::numeric_limits<double>::quiet_NaN();
  none.alert = false;
  FrameRecord miss = none;
  miss.estimated = false;
  miss.published_error = {1, 1, 1, 1, 1, 1};
  std::string path;
  const auto again = RoundTrip("pl.csv", {f, none, miss}, &path);
  ASSERT_EQ(again.size(), 3u);
  EXPECT_EQ(again[0].pl_position_m, 0.75);
  EXPECT_EQ(again[0].pl_attitude_deg, 1.125);
  EXPECT_EQ(again[0].al_position_m, 1.0);
  EXPECT_EQ(again[0].al_attitude_deg, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(again[0].alert);
  for (const auto& g : {again[1], again[2]}) {
    EXPECT_TRUE(std::isnan(g.pl_position_m));
    EXPECT_TRUE(std::isnan(g.pl_attitude_deg));
    EXPECT_TRUE(std::isnan(g.al_position_m));
    EXPECT_TRUE(std::isnan(g.al_attitude_deg));
    EXPECT_FALSE(g.alert);
  }
  EXPECT_EQ(FrameCsvRow(f).substr(FrameCsvRow(f).rfind(",3,") + 3),
            "0.75,1.125,1,inf,1,nan,nan,nan");
  // A frame not estimated writes no levels whatever its record holds.
  FrameRecord stale = f;
  stale.estimated = false;
  EXPECT_EQ(FrameCsvRow(stale).substr(FrameCsvRow(stale).rfind(",3,") + 3),
            "nan,nan,nan,nan,1,nan,nan,nan");
  // The file of the format before integrity: every column up to published_yaw_deg.
  std::ifstream in(path);
  std::string text, line;
  while (std::getline(in, line)) {
    size_t end = line.size();
    for (int i = 0; i < 8; ++i) end = line.rfind(',', end - 1);
    text += line.substr(0, end) + "\n";
  }
  const auto older = ReadFrameCsv(Write("older.csv", text));
  ASSERT_EQ(older.size(), 3u);
  EXPECT_EQ(older[0].error, f.error);
  EXPECT_TRUE(std::isnan(older[0].pl_position_m));
  EXPECT_FALSE(older[0].alert);
  EXPECT_TRUE(older[2].published);  // its held estimate is read, not taken from `estimated`
  EXPECT_EQ(older[2].published_error, miss.published_error);
  // Read and written again, the frames give the same cells.
  for (size_t i = 0; i < 3; ++i) {
    const std::string row = FrameCsvRow(again[i]);
    size_t end = row.size();
    for (int k = 0; k < 8; ++k) end = row.rfind(',', end - 1);
    EXPECT_NE(text.find(row.substr(0, end) + "\n"), std::string::npos) << row;
  }
}

// Visibility (issue 44): measured frames keep their fraction and pixels, a receiver in no view
// has 0 pixels and no fraction, an unmeasured frame neither; a file from before it reads as
// unmeasured.
TEST(Tables, VisibilityColumnsRoundTripAndTheOlderHeaderReads) {
  FrameRecord seen;
  seen.range_m = 150.0;
  seen.region = aar_geometry::Region::kA;
  seen.visible_fraction = 0.375;
  seen.visible_px = 1200;
  seen.visible_fraction_least = 0.125;
  FrameRecord in_no_view = seen;
  in_no_view.visible_fraction = std::numeric_limits<double>::quiet_NaN();
  in_no_view.visible_px = 0;
  in_no_view.visible_fraction_least = std::numeric_limits<double>::quiet_NaN();
  FrameRecord unmeasured = seen;
  unmeasured.visible_fraction = unmeasured.visible_px = unmeasured.visible_fraction_least =
      std::numeric_limits<double>::quiet_NaN();
  std::string path;
  const auto again = RoundTrip("visibility.csv", {seen, in_no_view, unmeasured}, &path);
  ASSERT_EQ(again.size(), 3u);
  EXPECT_EQ(again[0].visible_fraction, 0.375);
  EXPECT_EQ(again[0].visible_px, 1200);
  EXPECT_EQ(again[0].visible_fraction_least, 0.125);
  EXPECT_TRUE(std::isnan(again[1].visible_fraction));
  EXPECT_EQ(again[1].visible_px, 0);
  EXPECT_TRUE(std::isnan(again[2].visible_fraction));
  EXPECT_TRUE(std::isnan(again[2].visible_px));
  std::ifstream in(path);
  std::string text, line;
  std::string before_least;  // the format of the first two visibility columns
  while (std::getline(in, line)) {
    const size_t least = line.rfind(',');
    before_least += line.substr(0, least) + "\n";
    text += line.substr(0, line.rfind(',', line.rfind(',', least - 1) - 1)) + "\n";
  }
  EXPECT_EQ(ReadFrameCsv(Write("before_least.csv", before_least))[0].visible_px, 1200);
  EXPECT_TRUE(
      std::isnan(ReadFrameCsv(Write("before_least.csv", before_least))[0].visible_fraction_least));
  const auto older = ReadFrameCsv(Write("older_visibility.csv", text));
  ASSERT_EQ(older.size(), 3u);
  EXPECT_TRUE(std::isnan(older[0].visible_px));
  EXPECT_EQ(older[0].region, aar_geometry::Region::kA);
}

}  // namespace
}  // namespace aar_eval
