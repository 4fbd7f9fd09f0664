// Issue 27, the whole graph far out: the first 40 frames of the default approach (173.6 to
// 150.8 m, region A), in lockstep, each run launch/pipeline.launch on a ROS master of its own.
// tracking_outline fuses the receiver's outline in both images with ICP; tracking_robust, the
// same graph without it, is what the outline guards: stereo's few hundred points at 170 m fix
// neither range nor attitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "aar_testing/paths.h"
#include "aar_testing/pipeline_run.h"
#include "aar_testing/suite_approach.h"
#include "aar_testing/time_scale.h"

namespace {

constexpr int kFrames = 40;

struct PipelineRunStats {
  aar_testing::PipelineRun run;
  double range = 0.0;  // [m] the largest true range
  double worst = 0.0;  // [m] the largest position error of an estimated frame
  int wrong = 0;       // estimated frames more than 5 m off
};

struct RegionA {
  aar_testing::PipelineRun run;
  double x = 0.0, max_angle = 0.0;  // mean |x| [m]; largest mean |roll|, |pitch|, |yaw| [deg]
};

RegionA RunRegionA(const std::string& experiment) {
  RegionA a;
  a.run = aar_testing::RunPipeline(
      "outline_" + experiment, "experiment:=" + experiment + " frames:=" + std::to_string(kFrames),
      240.0 * aar_testing::TimeScale());
  Eigen::Vector3d angles = Eigen::Vector3d::Zero();
  for (const auto& f : a.run.frames) {
    if (!f.estimated) continue;
    a.x += std::abs(f.position_m.x()) / a.run.estimated;
    angles += f.rpy_deg.cwiseAbs() / a.run.estimated;
  }
  a.max_angle = angles.maxCoeff();
  std::printf(
      "[ region A ] %s: %d of %zu frames estimated, mean |x| %.3f m, largest mean angle "
      "%.3f deg\n",
      experiment.c_str(), a.run.estimated, a.run.frames.size(), a.x, a.max_angle);
  return a;
}

TEST(OutlineGraph, RegionAWithTheOutlineAndWithout) {
  const RegionA outline = RunRegionA("tracking_outline");
  ASSERT_TRUE(outline.run.error.empty()) << outline.run.error;
  EXPECT_EQ(outline.run.status, 0) << outline.run.output_dir << ".log";
  ASSERT_EQ(outline.run.frames.size(), size_t(kFrames));
  // Measured: 40 of 40, mean |x| 1.227 m, largest mean angle 0.216 deg (b54b7c6; 1.157 m before
  // the sparse matcher). The maneuver rule does not fire in these frames: with it off
  // (outline_maneuver_quality 1.0) the run is the same frame for frame. 1.2 m at 174-151 m is
  // under 1 % of range, what the outline's size gives far out (docs/TRACKING.md).
  EXPECT_EQ(outline.run.estimated, kFrames);
  EXPECT_LT(outline.x, 1.25);
  EXPECT_LT(outline.max_angle, 0.25);

  // Without the outline (the same graph otherwise): metres and degrees off, frames missed.
  const RegionA stereo = RunRegionA("tracking_robust");
  ASSERT_TRUE(stereo.run.error.empty()) << stereo.run.error;
  ASSERT_EQ(stereo.run.frames.size(), size_t(kFrames));
  // Measured: 38 of 40, mean |x| 3.522 m, largest mean angle 13.868 deg.
  EXPECT_GT(stereo.x, 2.5 * outline.x);
  EXPECT_GT(stereo.max_angle, 3.0 * outline.max_angle);
}

// Suite approach 1020 (seed 1, noise 2 grey levels, seeded 1020), its first 40 frames (174 to
// 151 m): stereo's starts are refused for 3.2 s (their outlines do not fit), and the first one
// taken is lost again. tracking_outline starts from the images alone (outline_image_start) on
// the first frame and holds the track.
TEST(OutlineGraph, AFarStartStereoCannotGiveComesFromTheImagesAlone) {
  const std::string path = aar_testing::WriteSuiteApproach(1020);
  const aar_testing::PipelineRun run = aar_testing::RunPipeline(
      "outline_image_start",
      "experiment:=tracking_outline flight_path:=" + path + " frames:=" + std::to_string(kFrames) +
          " noise_stddev:=2.0 noise_seed:=1020",
      240.0 * aar_testing::TimeScale());
  std::filesystem::remove(path);
  ASSERT_TRUE(run.error.empty()) << run.error;
  EXPECT_EQ(run.status, 0) << run.output_dir << ".log";
  ASSERT_EQ(run.frames.size(), size_t(kFrames));
  double x = 0.0, angle = 0.0;
  for (const auto& f : run.frames) {
    if (!f.estimated) continue;
    x += std::abs(f.position_m.x()) / run.estimated;
    angle = std::max(angle, f.rpy_deg.cwiseAbs().maxCoeff());
  }
  std::printf(
      "[ approach 1020 ] %d of %d frames estimated, mean |x| %.3f m, largest angle %.3f "
      "deg\n",
      run.estimated, kFrames, x, angle);
  // Measured: 40 of 40, 0.286 m, 0.524 deg. With outline_image_start: false, 6 of 40, 13.4 m
  // and 22.7 deg (a wrong stereo start, dropped after five frames).
  EXPECT_EQ(run.estimated, kFrames);
  EXPECT_LT(x, 0.35);
  EXPECT_LT(angle, 0.6);
}

// Suite approach 7003 (seed 7, held out: noise 2 grey levels, 10 Hz), 30 frames from 150 m: the
// boom hides half of the receiver from the camera that sees most of it and four fifths from the
// other (visible 53 % and 18 % of the silhouette). flight_partial starts from the part that is
// seen; flight and flight_both_views, which need 60 % of a view's outline, start at 92 m.
TEST(OutlineGraph, APartialViewStartsAt150m) {
  constexpr int kPartialFrames = 30;
  const std::string path = aar_testing::WriteSuiteApproach(7003);
  const aar_testing::PipelineRun run = aar_testing::RunPipeline(
      "outline_partial_start",
      "experiment:=flight_partial flight_path:=" + path + " start_time:=5.0 rate:=10 frames:=" +
          std::to_string(kPartialFrames) + " noise_stddev:=2.0 noise_seed:=7003",
      240.0 * aar_testing::TimeScale());
  std::filesystem::remove(path);
  ASSERT_TRUE(run.error.empty()) << run.error;
  EXPECT_EQ(run.status, 0) << run.output_dir << ".log";
  ASSERT_EQ(run.frames.size(), size_t(kPartialFrames));
  double mean = 0.0, worst = 0.0, range = 0.0;
  for (const auto& f : run.frames) {
    range = std::max(range, f.range_m);
    if (!f.estimated) continue;
    mean += f.position_m.norm() / run.estimated;
    worst = std::max(worst, f.position_m.norm());
  }
  std::printf(
      "[ approach 7003 ] from %.1f m: %d of %d frames estimated, position error mean %.3f m, "
      "largest %.3f m\n",
      range, run.estimated, kPartialFrames, mean, worst);
  // Measured: from 150.7 m, 22 of 30 (the first 6 frames' starts fit 0.44 to 0.64, below
  // outline_image_start_quality's 0.7; the 7th starts, seeing less than 60 % of its outline, and
  // is published from the second frame accepted after it on), 0.654 m mean, 2.039 m largest.
  // With flight_both_views (min_visible 0.6): 0 of 30.
  EXPECT_GT(range, 150.0);
  EXPECT_GE(run.estimated, 22);
  EXPECT_LT(mean, 0.7);
  EXPECT_LT(worst, 2.2);
}

// Suite approach 7003 with the RQ-4 under flight_partial and `registration` (its lines under
// `registration:`): `frames` frames from path time `start_time`.
PipelineRunStats RunRq4On7003(const std::string& tag, const std::string& registration,
                              double start_time, int frames) {
  const std::string receiver = aar_testing::ModelsDir() + "/rq4.yaml";
  const std::string path = aar_testing::WriteSuiteApproach(7003, receiver);
  const std::string experiment =
      (std::filesystem::temp_directory_path() / (tag + "_" + std::to_string(::getpid()) + ".yaml"))
          .string();
  {
    std::ofstream yaml(experiment);
    yaml << "include: flight_partial\nregistration:\n" << registration;
  }
  PipelineRunStats stats;
  stats.run = aar_testing::RunPipeline(
      tag,
      "experiment:=" + tag + " experiment_file:=" + experiment + " receiver:=" + receiver +
          " flight_path:=" + path + " start_time:=" + std::to_string(start_time) +
          " rate:=10 frames:=" + std::to_string(frames) + " noise_stddev:=2.0 noise_seed:=7003",
      240.0 * aar_testing::TimeScale());
  std::filesystem::remove(path);
  std::filesystem::remove(experiment);
  for (const auto& f : stats.run.frames) {
    stats.range = std::max(stats.range, f.range_m);
    if (!f.estimated) continue;
    stats.worst = std::max(stats.worst, f.position_m.norm());
    if (f.position_m.norm() > 5.0) ++stats.wrong;
  }
  std::printf(
      "[ rq4 7003, %s ] from %.1f m: %d of %zu frames estimated, %d more than 5 m off, largest "
      "%.3f m\n",
      tag.c_str(), stats.range, stats.run.estimated, stats.run.frames.size(), stats.wrong,
      stats.worst);
  return stats;
}

// The RQ-4 on 7003 from 104.6 m: partial starts fit its long, slender wings 30 to 50 m too far,
// and their own outlines go on agreeing with them. flight_partial checks a partial start's range
// against stereo's points until it is confirmed and drops those starts; with the check off
// (outline_image_start_partial_range_sigmas 0, and so outline_start_range_all false) one is
// confirmed and published.
TEST(OutlineGraph, StereoRefusesAPartialStartAtTheWrongRange) {
  const PipelineRunStats checked = RunRq4On7003("outline_partial_range",
                                                "  outline_image_start_partial_range_sigmas: 3.0\n"
                                                "  outline_start_range_all: true\n",
                                                15.0, 40);
  ASSERT_TRUE(checked.run.error.empty()) << checked.run.error;
  EXPECT_EQ(checked.run.status, 0) << checked.run.output_dir << ".log";
  ASSERT_EQ(checked.run.frames.size(), 40u);
  EXPECT_GT(checked.range, 104.0);
  // Measured: from 104.6 m, 37 of 40 estimated, none more than 5 m off, largest 2.097 m. With
  // the check off (range sigmas 0): 37 of 40 estimated, all 37 from a wrong partial start, 30 to
  // 52 m off.
  EXPECT_EQ(checked.wrong, 0);
  EXPECT_LT(checked.worst, 2.3);
  EXPECT_GE(checked.run.estimated, 36);
}

// Stereo's cue gives the range too (issue 44): the RQ-4 on 7003 from 174 m, the cue on. Around
// the cue's pixel the search also fits the slender wings of a farther, smaller receiver; stereo's
// points say how far the receiver is, and the search keeps to ranges within a pixel of their
// disparity (outline_image_start_cue_disparity_margin).
TEST(OutlineGraph, StereosCueSearchesAtItsRange) {
  const PipelineRunStats cued = RunRq4On7003("outline_cue_range",
                                             "  outline_image_start_cue_min_points: 10\n"
                                             "  outline_image_start_cue_disparity_margin: 1.0\n",
                                             0.0, 105);
  ASSERT_TRUE(cued.run.error.empty()) << cued.run.error;
  EXPECT_EQ(cued.run.status, 0) << cued.run.output_dir << ".log";
  ASSERT_EQ(cued.run.frames.size(), 105u);
  EXPECT_GT(cued.range, 173.0);
  // Measured: from 173.9 m, 12 of 105 estimated: starts 13 and 15 m off at 164 and 137 m (4 and 2
  // frames, in alert), then from 128 m within 2.5 m; 15.464 m the largest. With the margin 0 (every
  // range): 26 estimated, the last 14 from a start at 132 m 67 to 78 m off, 78.221 m the largest.
  EXPECT_LT(cued.worst, 16.5);
  EXPECT_GE(cued.run.estimated, 12);
}

}  // namespace
