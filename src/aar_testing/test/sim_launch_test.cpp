// launch/sim.launch ends on its own: on a flight path the sim refuses (naming it) and after the
// last frame with shutdown_at_end (quietly, no "REQUIRED process has died"). Each run on a master
// of its own, which roslaunch starts and stops.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

const std::string kRoot = aar_testing::WorkspaceRoot();
// roslaunch with its own master ends in well under this on the 2-core machine (about 5 s).
constexpr double kEndsWithinS = 45.0;

// status 124: `timeout` stopped roslaunch, which did not end on its own.
using Result = aar_testing::CommandResult;
const auto Sh = aar_testing::RunCommand;

// roslaunch launch/sim.launch ARGS on a master of its own, stopped by `timeout` after twice
// kEndsWithinS if it does not end.
Result RunSimLaunch(const std::string& args) {
  const int port = aar_testing::FreeRosPort();
  EXPECT_GT(port, 0);
  const std::string command =
      "ROS_MASTER_URI=http://localhost:" + std::to_string(port) + " timeout --signal=INT " +
      "--kill-after=20 " + std::to_string(static_cast<int>(2 * kEndsWithinS)) + " roslaunch -p " +
      std::to_string(port) + " " + kRoot + "/launch/sim.launch " + args;
  const Result r = Sh(command);
  std::printf("[ sim.launch ] %s: status %d after %.1f s\n", args.c_str(), r.status, r.seconds);
  return r;
}

bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(SimLaunch, BadFlightPathEndsTheLaunchNamingTheError) {
  const std::string csv = ::testing::TempDir() + "/sim_launch_bad_boom.csv";
  std::ofstream(csv) << "t,x,y,z,roll,pitch,yaw,boom_pitch,boom_roll,boom_extension\n"
                        "0,-40,0,-10,0,0,0,30,0,1\n"
                        "1,-39,0,-10,0,0,0,170,0,1\n";
  const Result r = RunSimLaunch("flight_path:=" + csv);
  EXPECT_NE(r.status, 124) << "roslaunch did not end on its own:\n" << r.output;
  EXPECT_LT(r.seconds, kEndsWithinS) << r.output;
  EXPECT_TRUE(Contains(r.output, csv + ": line 3: column 8 'boom_pitch': 170 deg is outside the "
                                       "limits of joint 'boom_pitch', 20 to 40 deg"))
      << r.output;
  // The sim's exit code, as roslaunch reports it (roslaunch itself exits 0 on a required death).
  EXPECT_TRUE(Contains(r.output, "REQUIRED process [sim-")) << r.output;
  EXPECT_TRUE(Contains(r.output, "exit code 1")) << r.output;
  std::filesystem::remove(csv);
}

TEST(SimLaunch, ShutdownAtEndEndsQuietly) {
  const Result r = RunSimLaunch("shutdown_at_end:=true frames:=2 rate:=20");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_LT(r.seconds, kEndsWithinS) << r.output;
  EXPECT_TRUE(Contains(r.output, "sim: flight path done, 2 frames")) << r.output;
  EXPECT_FALSE(Contains(r.output, "REQUIRED")) << r.output;
  EXPECT_FALSE(Contains(r.output, "has died")) << r.output;
  EXPECT_FALSE(Contains(r.output, "escalating")) << r.output;  // every node stopped on SIGINT
}

}  // namespace
