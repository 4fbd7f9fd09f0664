// Issue 44, more than one stereo rig: suite approach 7004 (seed 7, held out: noise 2 grey levels,
// 10 Hz) from 174 m, where the boom hides 90 % of the receiver from today's rig (its weaker camera
// sees 10 to 12 % of the silhouette) and the second rig of flight_two_rigs (share_mirror, on the
// boom's other side) sees all of it. Each run is launch/pipeline.launch on a master of its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "aar_testing/pipeline_run.h"
#include "aar_testing/suite_approach.h"
#include "aar_testing/time_scale.h"

namespace {

constexpr int kFrames = 20;

aar_testing::PipelineRun Fly(const std::string& experiment, const std::string& rigs,
                             const std::string& path) {
  return aar_testing::RunPipeline(
      "multirig_" + experiment,
      "experiment:=" + experiment + " rigs:=" + rigs + " flight_path:=" + path +
          " rate:=10 frames:=" + std::to_string(kFrames) + " noise_stddev:=2.0 noise_seed:=7004",
      300.0 * aar_testing::TimeScale());
}

TEST(MultiRig, FramesSeenOnlyByTheSecondRig) {
  const std::string path = aar_testing::WriteSuiteApproach(7004);
  const aar_testing::PipelineRun one = Fly("flight", "stereo", path);
  const aar_testing::PipelineRun two = Fly("flight_two_rigs", "stereo,share_mirror", path);
  std::filesystem::remove(path);
  for (const auto* run : {&one, &two}) {
    ASSERT_TRUE(run->error.empty()) << run->error;
    EXPECT_EQ(run->status, 0) << run->output_dir << ".log";
    ASSERT_EQ(run->frames.size(), size_t(kFrames));
  }
  double worst = 0.0, seen_one = 0.0, seen_two = 1.0;  // largest; least share of the best rig
  for (const auto& f : two.frames)
    if (f.estimated) worst = std::max(worst, f.position_m.norm());
  for (const auto& f : one.frames) seen_one = std::max(seen_one, f.visible_fraction_least);
  for (const auto& f : two.frames) seen_two = std::min(seen_two, f.visible_fraction_least);
  std::printf(
      "[ approach 7004 ] one rig %d of %d estimated; two rigs %d, mean error %.3f m, worst %.3f "
      "m, mean rotation %.3f deg; the weaker camera sees at most %.3f of the receiver with one "
      "rig, at least %.3f in the better rig of two\n",
      one.estimated, kFrames, two.estimated, two.mean_position_m, worst, two.mean_rotation_deg,
      seen_one, seen_two);
  // Measured: one rig 0 of 20; two rigs 20 of 20, mean 0.258 m, worst 0.959 m, 0.397 deg
  // (0.349 m, 0.319 deg with every view's errors independent: outline_rigs_share_errors false).
  // Registration told only the first rig (its stages running for both): 0 of 20.
  // Physics, not ours: one rig's weaker camera sees 0.127 of the receiver at most, the better
  // rig of two 1.000 at least (eval's visibility of both rigs).
  EXPECT_LT(seen_one, 0.15);
  EXPECT_GT(seen_two, 0.95);
  EXPECT_EQ(one.estimated, 0);
  EXPECT_EQ(two.estimated, kFrames);
  EXPECT_LT(two.mean_position_m, 0.4);
  EXPECT_LT(worst, 1.1);
  EXPECT_LT(two.mean_rotation_deg, 0.45);
}

}  // namespace
