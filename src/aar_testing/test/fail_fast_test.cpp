// Bad configuration ends a run at once, naming the cause (issue 31): a stage refusing a
// parameter ends its process (the nodelet manager with it) and so the launch; an experiment
// with a namespace no stage reads stops roslaunch before any node starts; the campaign driver
// records the cause and does not retry what would fail the same way. Before, the manager stayed
// up, every frame waited out the lockstep timeout (5 s) and the launch exited 0. A forged
// estimate ends a lockstep run too (issue 46).
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"
#include "aar_testing/time_scale.h"

namespace {

// One run of launch/pipeline.launch through the campaign driver's `fly` (a master of its own,
// bounded), 20 frames, with the experiment's settings from `file`.
aar_testing::CommandResult Fly(const std::string& file, const std::string& out) {
  return aar_testing::RunCommand(
      "timeout 300 python3 " + aar_testing::WorkspaceRoot() +
      "/scripts/campaign fly --experiment naive --frames 20 --start-time 40 --flight-path " +
      aar_testing::DefaultApproachPath() + " --out " + out + " experiment_file:=" + file);
}

std::string Write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A forger on a run's own master, 8 s into a 60-frame run: for each frame it publishes an
// estimate 1 km off at the frame's stamp, writing the registration's caller id (/aar_manager)
// into its connection header. The simulator finds a second node linked to /aar/pose_estimate
// (its address and port, not the name it gave) and ends the lockstep run, FATAL, naming it; the
// driver records that line as the reason and does not retry; eval took none of its estimates.
// Before: the run was "ok", 60 of 60 frames "estimated" with a mean |x| error of 760 m.
TEST(FailFast, AForgedEstimateEndsTheLockstepRunNamingIt) {
  const std::string out = "/tmp/aar_fail_fast_forged";
  aar_testing::RunCommand("rm -rf " + out);
  const std::string fly =
      "timeout 300 python3 " + aar_testing::WorkspaceRoot() +
      "/scripts/campaign fly --experiment naive --frames 60 --start-time 40 --flight-path " +
      aar_testing::DefaultApproachPath() + " --out " + out;
  const std::string port = "$(pgrep -af 'roslaunch -p [0-9]+ .*output_dir:=" + out +
                           "( |$)' | grep -o -- '-p [0-9]*' | head -n 1 | cut -d' ' -f2)";
  const auto r = aar_testing::RunCommand(
      fly + " & pid=$!; for i in $(seq 1 120); do p=" + port +
      "; [ -n \"$p\" ] && break; sleep 0.5; done; sleep 8; ROS_MASTER_URI=http://localhost:$p "
      "ROS_HOSTNAME=localhost timeout 120 rosrun aar_testing forge_estimates.py /aar_manager "
      "100; wait $pid");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output, std::regex("FAILED \\([0-9]+ of 60 frames, 1 attempt\\(s\\)\\): \\[FATAL\\] .*sim: "
                           "frame loop stopped: another node publishes on /aar/pose_estimate at "
                           "http://localhost:[0-9]+/ \\(the master lists /aar_manager at "
                           "http://localhost:[0-9]+/\\)")))
      << r.output;
  EXPECT_NE(r.output.find("forger: "), std::string::npos) << r.output;
  std::smatch mean;
  const std::string log = Read(out + "/launch.log");
  ASSERT_TRUE(
      std::regex_search(log, mean, std::regex(R"(eval: region all: .* mean \|x\| ([0-9.e+-]+) m)")))
      << log;
  EXPECT_LT(std::stod(mean[1]), 5.0) << "a forged estimate was taken: " << mean[0];  // 0.46 m
  EXPECT_NE(Read(out + "/run.json").find("another node publishes on /aar/pose_estimate"),
            std::string::npos);
}

TEST(FailFast, AStageRefusingAParameterEndsTheRunNamingTheKey) {
  const std::string file =
      Write("/tmp/aar_fail_fast_value.yaml", "registration:\n  icp_plane_sigma: -1.0\n");
  const auto r = Fly(file, "/tmp/aar_fail_fast_value");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("icp_plane_sigma"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("registration cannot start: its process ends"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1 attempt(s)"), std::string::npos) << "retried: " << r.output;
  // Measured 2.7 to 3.1 s on issue 31's machine (was 6.1 s: the simulator, still building its
  // world, held the launch up; 106 s before the stage ended its process). On a later machine of
  // the same kind 4.5 to 5.6 s, and the same at 708b1ef (6 runs, 3 each, side by side). What it
  // guards: the 20 frames would take 5 s each.
  EXPECT_LT(r.seconds, 8.0 * aar_testing::TimeScale()) << r.output;
  EXPECT_NE(Read("/tmp/aar_fail_fast_value/run.json").find("\"reason\""), std::string::npos);
}

TEST(FailFast, AnExperimentNamespaceNoStageReadsStopsTheLaunchBeforeAnyNode) {
  const std::string file =
      Write("/tmp/aar_fail_fast_namespace.yaml", "registraton:\n  track: true\n");
  const auto r = Fly(file, "/tmp/aar_fail_fast_namespace");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("unknown namespace 'registraton' (no stage reads it"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1 attempt(s)"), std::string::npos) << "retried: " << r.output;
  EXPECT_LT(r.seconds, 5.0 * aar_testing::TimeScale()) << r.output;  // measured 0.8 to 0.9 s
}

// An experiment starts from others (include): a user's file beside no shipped experiment
// includes flight and changes one key; the resolved settings are flight's with that key, and
// --show names the file each setting comes from. A missing include and a circle of includes are
// named; a launch of an experiment with a missing include stops before any node starts.
TEST(FailFast, AnExperimentIncludesItsBasesAndAMissingOneIsNamed) {
  const std::string dir = "/tmp/aar_fail_fast_include";
  aar_testing::RunCommand("rm -rf " + dir + " && mkdir -p " + dir);
  const std::string check = "python3 " + aar_testing::WorkspaceRoot() +
                            "/src/aar_ros_common/scripts/check_experiment.py ";
  const std::string mine =
      Write(dir + "/mine.yaml", "include: flight\nregistration:\n  max_sensed_points: 2000\n");
  auto r = aar_testing::RunCommand(check + mine + " --resolved " + dir + "/resolved.yaml");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string resolved = Read(dir + "/resolved.yaml");
  for (const char* line : {"  max_sensed_points: 2000\n", "  outline: true\n", "  boom: true\n",
                           "  alert_overbound_factor:\n", "    matcher: sparse\n"})
    EXPECT_NE(resolved.find(line), std::string::npos) << line << " not in\n" << resolved;
  r = aar_testing::RunCommand(check + "--show " + mine);
  EXPECT_TRUE(std::regex_search(r.output, std::regex("registration/max_sensed_points: +2000 +# "
                                                     "/tmp/aar_fail_fast_include/mine\\.yaml")))
      << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output,
      std::regex("registration/outline: +true +# config/experiments/tracking_outline.yaml")))
      << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output, std::regex("registration/max_iterations: +[0-9]+ +# config/registration.yaml")))
      << r.output;
  r = aar_testing::RunCommand(check + Write(dir + "/lost.yaml", "include: fligth\n"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("lost.yaml: includes 'fligth', but there is no fligth.yaml beside it"),
            std::string::npos)
      << r.output;
  Write(dir + "/a.yaml", "include: b\n");
  r = aar_testing::RunCommand(check + Write(dir + "/b.yaml", "include: a\n"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("b.yaml: includes itself (through "), std::string::npos) << r.output;
  // A sim rig's `mount: NAME` stands for config/mounts/NAME.yaml's keys, the rig's own winning;
  // a mount that is not there is named.
  const std::string rigs = Write(dir + "/rigs.yaml",
                                 "include: flight\nsim:\n  rigs:\n  - name: stereo\n"
                                 "  - {name: two, mount: share_mirror, camera_z: -5.0}\n");
  r = aar_testing::RunCommand(check + rigs + " --resolved " + dir + "/rigs_resolved.yaml");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string rig = Read(dir + "/rigs_resolved.yaml");
  for (const char* line : {"camera_x: -15.0\n", "camera_y: -1.0\n", "camera_z: -5.0\n"})
    EXPECT_NE(rig.find(line), std::string::npos) << line << " not in\n" << rig;
  EXPECT_EQ(rig.find("mount"), std::string::npos) << rig;
  r = aar_testing::RunCommand(check + Write(dir + "/no_mount.yaml",
                                            "sim:\n  rigs:\n  - name: stereo\n"
                                            "  - {name: two, mount: nowhere}\n"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("config/mounts/nowhere.yaml: not readable"), std::string::npos)
      << r.output;
  r = Fly(dir + "/lost.yaml", dir + "/run");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("includes 'fligth'"), std::string::npos) << r.output;
  EXPECT_LT(r.seconds, 5.0 * aar_testing::TimeScale()) << r.output;
}

TEST(FailFast, EveryShippedExperimentHasOnlyTheStagesNamespaces) {
  const auto r = aar_testing::RunCommand(
      "for f in " + aar_testing::ConfigDir() + "/experiments/*.yaml; do python3 " +
      aar_testing::WorkspaceRoot() +
      "/src/aar_ros_common/scripts/check_experiment.py $f >/dev/null || exit 1; done");
  EXPECT_EQ(r.status, 0) << r.output;
}

}  // namespace
