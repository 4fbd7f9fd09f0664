// Raw cameras (issue 15): the simulator's distorted, slightly rotated cameras (config/sim.yaml
// raw_images) through image_proc's rectify nodelets (launch/pipeline.launch rectify:=true) give
// pose errors near contact within a stated bound of the ideal pinhole cameras; the same raw
// images fed to aar_stereo as image_rect without rectification earn its warning and wrong poses.
// Each run is launch/pipeline.launch on a ROS master of its own (as full_graph_test), experiment
// dynamic, 8 frames from path time 47 s (36.9 to 36.5 m, region C), in lockstep.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "aar_testing/pipeline_run.h"

namespace {

constexpr int kFrames = 8;
constexpr double kStart = 47.0;  // [s] path time

using FrameError = aar_testing::PipelineFrame;
using PipelineRun = aar_testing::PipelineRun;

PipelineRun RunPipeline(const std::string& tag, const std::string& args,
                        const std::string& experiment = "dynamic") {
  PipelineRun run = aar_testing::RunPipeline(
      "rawcam_" + tag, "experiment:=" + experiment + " frames:=" + std::to_string(kFrames) +
                           " start_time:=" + std::to_string(kStart) + " " + args);
  EXPECT_TRUE(run.error.empty()) << run.error;
  EXPECT_EQ(run.status, 0) << "(log: " << run.output_dir << ".log)";
  std::printf("[ rawcam ] %s (%s): %d of %zu frames estimated, mean error %.4f m, %.3f deg\n",
              tag.c_str(), args.c_str(), run.estimated, run.frames.size(), run.mean_position_m,
              run.mean_rotation_deg);
  return run;
}

const char kWarning[] = "stereo: camera infos with distortion on image_rect input";

// The largest difference between two runs' errors frame by frame, as vectors: [m], [deg].
std::pair<double, double> WorstDifference(const PipelineRun& a, const PipelineRun& b) {
  double position = 0.0, rotation = 0.0;
  for (size_t i = 0; i < std::min(a.frames.size(), b.frames.size()); ++i) {
    const FrameError &x = a.frames[i], &y = b.frames[i];
    EXPECT_NEAR(x.t, y.t, 1e-9);
    position = std::max(position, (y.position_m - x.position_m).norm());
    rotation = std::max(rotation, (y.rpy_deg - x.rpy_deg).norm());
  }
  std::printf("[ rawcam ] per frame, rectified - pinhole: at most %.4f m, %.3f deg\n", position,
              rotation);
  return {position, rotation};
}

// Distorted + rectified against pinhole, frame by frame. Measured here (commit of this test,
// 2 cores shared with other jobs): pinhole mean 0.0219 m, 0.162 deg; rectified 0.0262 m,
// 0.143 deg; per frame the two errors differ by at most 0.032 m and 0.29 deg (as vectors).
// With the rectification off (raw_images:=true, rectify false) the errors are metres
// (mean 8.2 m): the bounds fail.
TEST(RawCameras, RectifiedRawCamerasMatchPinholeNearContact) {
  const PipelineRun pinhole = RunPipeline("pinhole", "");
  const PipelineRun rectified = RunPipeline("rectified", "rectify:=true");
  ASSERT_EQ(pinhole.frames.size(), size_t(kFrames));
  ASSERT_EQ(rectified.frames.size(), size_t(kFrames));
  EXPECT_EQ(pinhole.estimated, kFrames);
  EXPECT_EQ(rectified.estimated, kFrames);
  const auto [worst_position, worst_rotation] = WorstDifference(pinhole, rectified);
  EXPECT_LT(worst_position, 0.045);                                         // [m] measured 0.032
  EXPECT_LT(worst_rotation, 0.4);                                           // [deg] measured 0.29
  EXPECT_LT(rectified.mean_position_m, pinhole.mean_position_m + 0.01);     // measured +0.0043 m
  EXPECT_LT(rectified.mean_rotation_deg, pinhole.mean_rotation_deg + 0.1);  // measured -0.018
  // The rectify nodelets ran (loaded into the processing manager), and aar_stereo, told the
  // images are rectified upstream, did not warn about the raw cameras' D.
  EXPECT_EQ(rectified.log.find(kWarning), std::string::npos) << "warned behind image_proc";
  EXPECT_NE(rectified.log.find("stereo/left/rectify"), std::string::npos);
  EXPECT_EQ(rectified.log.find("Failed to load nodelet"), std::string::npos);
}

// A further rig's raw cameras are rectified as the first's (launch/include/rig.launch rectify):
// flight_two_rigs on raw images matches its pinhole run frame by frame, and the second rig's
// rectify nodelets ran and its clouds came. Without them its stereo gets no images: registration
// names every frame registered without the rig (measured, the nodelets off: 8 of 8 frames from
// the first rig alone, 0.0061 m at most from the pinhole run).
TEST(RawCameras, AFurtherRigsRawCamerasAreRectifiedToo) {
  const std::string rigs = "rigs:=stereo,share_mirror";
  const PipelineRun pinhole = RunPipeline("two_rigs_pinhole", rigs, "flight_two_rigs");
  const PipelineRun rectified =
      RunPipeline("two_rigs_rectified", rigs + " rectify:=true", "flight_two_rigs");
  ASSERT_EQ(pinhole.frames.size(), size_t(kFrames));
  ASSERT_EQ(rectified.frames.size(), size_t(kFrames));
  EXPECT_EQ(pinhole.estimated, kFrames);
  EXPECT_EQ(rectified.estimated, kFrames);
  const auto [worst_position, worst_rotation] = WorstDifference(pinhole, rectified);
  EXPECT_LT(worst_position, 0.005);  // [m] measured 0.0023
  EXPECT_LT(worst_rotation, 0.06);   // [deg] measured 0.028
  EXPECT_EQ(rectified.log.find(kWarning), std::string::npos) << "warned behind image_proc";
  EXPECT_NE(rectified.log.find("share_mirror/left/rectify"), std::string::npos);
  EXPECT_NE(rectified.log.find("share_mirror/right/rectify"), std::string::npos);
  EXPECT_EQ(rectified.log.find("registered without the clouds of"), std::string::npos)
      << "a rig's clouds did not come";
}

// The raw images fed as image_rect, nothing rectifying them (a rig's image_raw remapped): the
// warning names the topic and the D values, and the poses are wrong by metres (measured mean
// 8.24 m, 49 deg).
TEST(RawCameras, UnrectifiedRawCamerasAreWarnedAbout) {
  const PipelineRun raw = RunPipeline("unrectified", "raw_images:=true");
  const size_t at = raw.log.find(kWarning);
  ASSERT_NE(at, std::string::npos) << "no warning for distorted images on image_rect";
  const std::string warning = raw.log.substr(at, raw.log.find('\n', at) - at);
  EXPECT_NE(warning.find("/stereo/left/camera_info plumb_bob D = [-0.26, 0.09, 0.0006, -0.0004, "
                         "-0.012]"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("/stereo/right/camera_info plumb_bob D = [-0.24"), std::string::npos)
      << warning;
  EXPECT_GT(raw.mean_position_m, 2.0);  // [m] measured 8.24: matching distorted images is wrong
}

}  // namespace
