// Issue 16, the whole graph in the realistic world (config/realism/realistic.yaml: terrain and
// clouds behind the receiver, the sun, the propellers, the sensor effects, moderate turbulence),
// near contact: 20 frames from path time 47 s (36.8 to 36.2 m, region C), in lockstep, each run
// launch/pipeline.launch on a ROS master of its own.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "aar_testing/paths.h"
#include "aar_testing/pipeline_run.h"
#include "aar_testing/time_scale.h"

namespace {

constexpr int kFrames = 20;
constexpr int kSettled = 8;  // the last frames: a track started near contact has settled

aar_testing::PipelineRun RunRealistic(const std::string& experiment) {
  return aar_testing::RunPipeline(
      "realistic_" + experiment,
      "experiment:=" + experiment + " frames:=" + std::to_string(kFrames) +
          " start_time:=47 sim_config:=" + aar_testing::WorkspaceRoot() +
          "/config/realism/realistic.yaml",
      240.0 * aar_testing::TimeScale());
}

// tracking_robust acquires from its densest-ball seed and holds the receiver within centimetres;
// tracking, whose acquiring seed is the centroid of every point, is dragged off by the
// background's far points and estimates nothing (the option this guards: seed_points).
// A track started near contact first coasts on a velocity it does not know yet (up to 0.9 m off
// over its first 7 frames here), then settles; the last kSettled frames are the estimator's
// steady state.
TEST(RealisticWorld, TrackingRobustEstimatesNearContactWhereTrackingCannotAcquire) {
  const aar_testing::PipelineRun robust = RunRealistic("tracking_robust");
  ASSERT_TRUE(robust.error.empty()) << robust.error;
  EXPECT_EQ(robust.status, 0) << robust.output_dir << ".log";
  ASSERT_EQ(robust.frames.size(), size_t(kFrames));
  double position = 0.0, rotation = 0.0;
  int settled = 0;
  for (size_t i = kFrames - kSettled; i < robust.frames.size(); ++i) {
    if (!robust.frames[i].estimated) continue;
    ++settled;
    position += robust.frames[i].position_m.norm();
    rotation += robust.frames[i].rpy_deg.norm();
  }
  ASSERT_GT(settled, 0);
  std::printf(
      "[ realistic ] tracking_robust: %d of %d frames, the last %d: %d estimated, mean "
      "%.4f m, %.3f deg\n",
      robust.estimated, kFrames, kSettled, settled, position / settled, rotation / settled);
  EXPECT_GE(robust.estimated, kFrames - 2);  // measured 19 of 20
  EXPECT_EQ(settled, kSettled);
  EXPECT_LT(position / settled, 0.045);  // [m] measured 0.0362 (0.0354 before gate_receiver)
  EXPECT_LT(rotation / settled, 0.35);   // [deg] measured 0.309 (0.252 before gate_receiver)

  const aar_testing::PipelineRun tracking = RunRealistic("tracking");
  ASSERT_TRUE(tracking.error.empty()) << tracking.error;
  ASSERT_EQ(tracking.frames.size(), size_t(kFrames));
  EXPECT_EQ(tracking.estimated, 0);  // measured 0 of 20: it never acquires
}

}  // namespace
