// Integrity in the whole graph: a deliberately wrong start (registration's fault_start_offset:
// every new track starts 8 m further out than its acquisition found) on 30 frames of the default
// approach in region B (58 to 51 m, alert limit 2 m), in lockstep through launch/pipeline.launch.
// With the confirmation a new track needs (integrity_confirm_frames), every start is published in
// alert and no frame misleads; with it off, the wrong start is published as usable.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <aar_eval/integrity.h>
#include <aar_eval/tables.h>

#include "aar_testing/paths.h"
#include "aar_testing/pipeline_run.h"
#include "aar_testing/time_scale.h"

namespace {

constexpr int kFrames = 30;

// config/experiments/flight.yaml with `keys` (lines of registration's) added, written to a
// temporary file whose path is returned.
std::string FlightWith(const std::string& tag, const std::string& keys) {
  std::ifstream in(aar_testing::ConfigDir() + "/experiments/flight.yaml");
  std::ostringstream out;
  bool added = false;
  for (std::string line; std::getline(in, line);) {
    out << line << "\n";
    if (line == "registration:") {
      out << keys;
      added = true;
    }
  }
  EXPECT_TRUE(added) << "flight.yaml has no 'registration:' line";
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("aar_integrity_" + tag + "_" + std::to_string(getpid()) + ".yaml"))
                               .string();
  std::ofstream(path) << out.str();
  return path;
}

struct WrongStart {
  aar_testing::PipelineRun run;
  std::vector<aar_eval::FrameRecord> frames;
  aar_eval::IntegrityStats all;
  int starts = 0, starts_in_alert = 0;
};

WrongStart RunWrongStart(const std::string& tag, int confirm_frames) {
  const std::string yaml =
      FlightWith(tag, "  fault_start_offset: 8.0\n  integrity_confirm_frames: " +
                          std::to_string(confirm_frames) + "\n");
  WrongStart w;
  w.run = aar_testing::RunPipeline("integrity_" + tag,
                                   "experiment:=flight experiment_file:=" + yaml +
                                       " start_time:=22 frames:=" + std::to_string(kFrames),
                                   240.0 * aar_testing::TimeScale());
  std::filesystem::remove(yaml);
  if (!w.run.error.empty()) return w;
  w.frames = aar_eval::ReadFrameCsv(w.run.output_dir + "/frames.csv");
  const auto stats = aar_eval::ComputeIntegrityStats(w.frames);
  if (stats.count("all")) w.all = stats.at("all");
  for (const auto& f : w.frames) {
    if (f.track != "started") continue;
    ++w.starts;
    w.starts_in_alert += f.alert;
  }
  std::printf(
      "[ wrong start ] confirm_frames %d: %d of %zu frames estimated, %d in alert, %d starts "
      "(%d in alert), %d misleading, %d hazardously misleading, %d available\n",
      confirm_frames, w.all.estimated, w.frames.size(), w.all.alert, w.starts, w.starts_in_alert,
      w.all.misleading, w.all.hazardous, w.all.available);
  return w;
}

TEST(IntegrityGraph, AWrongStartIsPublishedInAlertUntilConfirmed) {
  const WrongStart confirmed = RunWrongStart("confirmed", 5);
  ASSERT_TRUE(confirmed.run.error.empty()) << confirmed.run.error;
  EXPECT_EQ(confirmed.run.status, 0) << confirmed.run.output_dir << ".log";
  ASSERT_EQ(confirmed.frames.size(), size_t(kFrames));
  // Measured: 1 start, 7.97 m off, in alert with the 5 frames after it (the outline's maneuver
  // rule put the track back on the receiver at the next frame, 3 mm off); 0 misleading; 24
  // frames available (9 frames after it and 20 available before flight's covariance terms).
  EXPECT_GE(confirmed.starts, 1);
  EXPECT_EQ(confirmed.starts_in_alert, confirmed.starts);
  EXPECT_EQ(confirmed.all.misleading, 0);
  EXPECT_EQ(confirmed.all.hazardous, 0);

  // The same with the confirmation off: the wrong start is published as usable, 8 m off where
  // 2 m is the limit.
  const WrongStart trusting = RunWrongStart("trusting", 0);
  ASSERT_TRUE(trusting.run.error.empty()) << trusting.run.error;
  ASSERT_EQ(trusting.frames.size(), size_t(kFrames));
  // Measured: the start not in alert, 1 misleading and hazardously misleading frame.
  EXPECT_GE(trusting.starts, 1);
  EXPECT_LT(trusting.starts_in_alert, trusting.starts);
  EXPECT_GE(trusting.all.hazardous, 1);
}

}  // namespace
