// scripts/replay on the committed sample bag reproduces the live run that recorded it, and on
// broken bags it names what is wrong and exits (status 2) without starting the graph.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <aar_eval/tables.h>
#include <aar_sim/flight_path.h>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"
#include "aar_testing/time_scale.h"

namespace {

const std::string kRoot = aar_testing::WorkspaceRoot();

using Result = aar_testing::CommandResult;
const auto Sh = aar_testing::RunCommand;

// Sanitized runs are slower (aar_testing::TimeScale): replay rates are divided by it, timeouts
// multiplied by it.
const double kScale = aar_testing::TimeScale();
// `timeout` for a command that takes up to `seconds` in a plain build.
std::string Timeout(double seconds) { return "timeout " + std::to_string(seconds * kScale) + " "; }
std::string Rate(double rate) { return " --rate " + std::to_string(rate / kScale) + " "; }

// The experiment these tests' bounds were measured with (the sample's live run's); scripts/replay
// flies flight unless told.
const char kExperiment[] = " --experiment dynamic ";

// scripts/replay at `rate` (its default, 0.25, unless given) of the recorded speed.
std::string Replay(const std::string& bag, const std::string& out, double rate = 0.25) {
  return Timeout(300) + kRoot + "/scripts/replay --no-build" + kExperiment + Rate(rate) + bag +
         " --out " + out;
}

// scripts/replay's comparison with the live run, every frame alike in having an estimate: `m`
// gets the frames compared, of how many, and the largest difference [m], [deg].
bool ComparedAlike(const std::string& output, std::smatch& m) {
  return std::regex_search(output, m,
                           std::regex("(\\d+) of (\\d+) frames compared, 0 differ in having an "
                                      "estimate; largest difference ([0-9.e+-]+) m, "
                                      "([0-9.e+-]+) deg"));
}

TEST(Replay, SampleBagReproducesTheLiveRun) {
  const std::string out = ::testing::TempDir() + "/replay_sample";
  std::filesystem::remove_all(out);
  // A tenth of the recorded rate: at 0.25 a sanitized graph fell behind the bag.
  const Result r = Sh(Replay(kRoot + "/rosbags/sample_contact.bag", out, 0.1));
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.status, 0);
  std::smatch m;
  ASSERT_TRUE(ComparedAlike(r.output, m));
  EXPECT_EQ(m[1], m[2]);
  EXPECT_EQ(m[1], "30");
  EXPECT_LE(std::stod(m[3]), 1e-6);  // lockstep recording, deterministic graph: the same poses
  EXPECT_LE(std::stod(m[4]), 1e-6);
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
}

// Issue 44: a bag of two rigs (flight_two_rigs, its live run recorded with
// rigs:=stereo,share_mirror: 15 lockstep frames at 10 Hz from 168 m, far out) holds the further
// rig's cameras, scripts/replay finds both rigs in it and replays flight_two_rigs with them: the
// replay reproduces the live run's frames.csv (scripts/make-sample-bag writes it beside the bag). A
// one-rig experiment replays rig 0 of the same bag; a bag without the further rig is refused,
// naming both.
TEST(Replay, TwoRigBagReproducesTheLiveRun) {
  const std::string dir = ::testing::TempDir() + "/replay_two_rigs";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string bag = dir + "/two_rigs.bag";
  const Result made =
      Sh(Timeout(240) + kRoot + "/scripts/make-sample-bag --no-build --experiment flight_two_rigs" +
         " --start 0 --frames 15 --out " + bag);
  std::printf("%s", made.output.c_str());
  ASSERT_EQ(made.status, 0);
  EXPECT_NE(made.output.find("/share_mirror/left/image_rect"), std::string::npos);

  const Result r = Sh(Timeout(240) + kRoot + "/scripts/replay --no-build --experiment " +
                      "flight_two_rigs" + Rate(0.25) + bag + " --out " + dir + "/two");
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 0);
  std::smatch m;
  ASSERT_TRUE(ComparedAlike(r.output, m));
  EXPECT_EQ(m[1], "15");
  EXPECT_EQ(m[2], "15");
  // 0 m and 0 deg measured: a lockstep recording through a deterministic graph, both rigs.
  EXPECT_LE(std::stod(m[3]), 1e-6);
  EXPECT_LE(std::stod(m[4]), 1e-6);
  EXPECT_NE(r.output.find("(15 of 15 frames processed, 15 with an estimate)"), std::string::npos);

  // flight (one rig) on the same bag: rig 0 only, every frame processed; its poses are not the
  // two rigs' (so the comparison above tells whether the second rig was replayed).
  const Result one =
      Sh(Timeout(240) + kRoot + "/scripts/replay --no-build --experiment flight" + Rate(0.25) +
         bag + " --compare " + dir + "/two_rigs.flight_two_rigs.live.csv --out " + dir + "/one");
  std::printf("%s", one.output.c_str());
  EXPECT_NE(one.output.find("the bag holds the rigs stereo,share_mirror; flight flies stereo"),
            std::string::npos);
  EXPECT_NE(one.output.find("(15 of 15 frames processed"), std::string::npos);
  ASSERT_TRUE(std::regex_search(one.output, m,
                                std::regex("15 of 15 frames compared, \\d+ differ in having an "
                                           "estimate; largest difference ([0-9.e+-]+) m")));
  EXPECT_GT(std::stod(m[1]), 0.9);  // 0.976 m measured (0.537 deg)

  // The one-rig sample bag is refused for flight_two_rigs, before anything starts.
  const Result refused =
      Sh(Timeout(60) + kRoot + "/scripts/replay --no-build --experiment flight_two_rigs " + kRoot +
         "/rosbags/sample_contact.bag --out " + dir + "/refused");
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("experiment 'flight_two_rigs' flies the rigs stereo,share_mirror, "
                                "but bag '" +
                                kRoot + "/rosbags/sample_contact.bag' holds stereo"),
            std::string::npos)
      << refused.output;
}

// Frames without an estimate are not a success. At 20 times the recorded rate the graph falls
// behind on 2 cores and drops frames; the script once said "30 of 30 frames" and exited 0 (it
// counted rows, not estimates). Now it counts both and exits 3.
TEST(Replay, FramesWithoutAnEstimateAreCountedNotASuccess) {
  const std::string out = ::testing::TempDir() + "/replay_fast";
  std::filesystem::remove_all(out);
  const Result r =
      Sh(Timeout(300) + kRoot + "/scripts/replay --no-build --no-compare" + kExperiment +
         "--rate 20 " + kRoot + "/rosbags/sample_contact.bag --out " + out);
  std::printf("%s", r.output.c_str());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      r.output, m, std::regex("\\((\\d+) of 30 frames processed, (\\d+) with an estimate\\)")));
  const int estimated = std::stoi(m[2]);
  ASSERT_LT(estimated, std::stoi(m[1])) << "the graph kept up at rate 20: no miss to count";
  EXPECT_EQ(r.status, std::stoi(m[1]) == 30 ? 3 : 1);
  EXPECT_NE(r.output.find(std::to_string(std::stoi(m[1]) - estimated) + " of " + m[1].str() +
                          " frames have no estimate"),
            std::string::npos);
}

// A tf outage (injected: tf_filter relays nothing from 47.0 to 48.0 s of bag time): the frames in
// it have no truth; each is named and counted, none is lost without a word.
TEST(Replay, TfOutageFramesAreNamedAndCounted) {
  const std::string out = ::testing::TempDir() + "/replay_outage";
  std::filesystem::remove_all(out);
  const Result r =
      Sh(Timeout(300) + kRoot + "/scripts/replay --no-build --no-compare" + kExperiment +
         Rate(0.25) + "--tf-outage 47,1 " + kRoot + "/rosbags/sample_contact.bag --out " + out);
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 1);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m,
                                std::regex("replay: (\\d+) frames had no truth \\(tf to the truth "
                                           "frame missing at their stamp\\)")));
  // 47.0 to 47.9 s: 10 frames, give or take the edges of the outage.
  EXPECT_GE(std::stoi(m[1]), 8);
  EXPECT_LE(std::stoi(m[1]), 12);
  EXPECT_EQ(r.output.find("frames reached eval"), std::string::npos)
      << "frames lost without a word";
  // The ledger counts the outage's frames as eval's (no truth), and every frame as reaching eval.
  EXPECT_NE(r.output.find(m[1].str() + " dropped (eval no_truth " + m[1].str() + ")"),
            std::string::npos);
  EXPECT_NE(r.output.find("0 of 30 frames sent never reached eval"), std::string::npos);
  EXPECT_EQ(Sh("grep -c 'tf outage starts' " + out + "/dynamic/launch.log").output, "1\n");
}

// A stage killed mid-flight (kill -9) comes back by itself: replay.launch respawns stereo,
// occlusion and registration (respawn:=true, its default) and eval, outside the manager, keeps
// counting. Before, a kill -9 of registration ended the whole replay. `pattern` picks the process
// among this replay's own (its process tree), never another run's.
void KillMidFlightAndResume(const std::string& name, const std::string& pattern) {
  const std::string out = ::testing::TempDir() + "/replay_kill_" + name;
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const std::string csv = out + "/dynamic/frames.csv";
  // At a tenth of the recorded rate (30 s of playback), a stage has time to come back.
  ASSERT_EQ(Sh("(" + Timeout(300) + kRoot + "/scripts/replay --no-build --no-compare" +
               kExperiment + Rate(0.1) + kRoot + "/rosbags/sample_contact.bag --out " + out +
               " > " + out + "/replay.log 2>&1; " + "echo $? > " + out +
               "/status) > /dev/null 2>&1 & echo $! > " + out + "/pid")
                .status,
            0);
  // Once 8 frames are in, kill the process.
  auto rows = [&] { return Sh("[ -f " + csv + " ] && tail -n +2 " + csv + " | wc -l || echo 0"); };
  const auto start = std::chrono::steady_clock::now();
  while (std::stoi(rows().output) < 8 &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(120) * kScale)
    ::usleep(200000);
  ASSERT_GE(std::stoi(rows().output), 8) << Sh("cat " + out + "/replay.log").output;
  // The replay's process tree, breadth first from the backgrounded shell.
  const Result killed =
      Sh("tree=$(cat " + out + "/pid); new=$tree; while [ -n \"$new\" ]; do " +
         "new=$(for p in $new; do pgrep -P $p; done | tr '\\n' ' '); tree=\"$tree $new\"; done; " +
         "for p in $tree; do if grep -q -- '" + pattern + "' /proc/$p/cmdline 2>/dev/null; then " +
         "kill -9 $p && echo killed $p; fi; done");
  std::printf("[ replay ] %s at frame %s: %s", name.c_str(), rows().output.c_str(),
              killed.output.c_str());
  ASSERT_NE(killed.output.find("killed"), std::string::npos) << "no process matched " << pattern;
  while (!std::filesystem::exists(out + "/status") &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(300) * kScale)
    ::usleep(500000);
  const std::string log = Sh("cat " + out + "/replay.log " + out + "/dynamic/launch.log").output;
  ASSERT_TRUE(std::filesystem::exists(out + "/status")) << log;
  // Every frame reached eval; the frames after the restart have estimates again.
  EXPECT_NE(log.find("(30 of 30 frames processed"), std::string::npos) << log;
  EXPECT_NE(log.find("restarting process"), std::string::npos) << log;  // roslaunch respawned it
  const auto records = aar_eval::ReadFrameCsv(csv);
  ASSERT_EQ(records.size(), 30u);
  int last_estimated = 0;
  for (size_t i = 22; i < records.size(); ++i) last_estimated += records[i].estimated;
  std::printf("[ replay ] %s: %d of the last 8 frames estimated\n", name.c_str(), last_estimated);
  EXPECT_GE(last_estimated, 7);
}

TEST(Replay, KilledRegistrationComesBackAndEstimatesAgain) {
  KillMidFlightAndResume("registration", "RegistrationNodelet");
}

TEST(Replay, KilledManagerComesBackAndEstimatesAgain) {
  KillMidFlightAndResume("manager", "__name:=aar_manager");
}

// What a rig records (rosbags/sample_rig_contact.bag: scripts/make-sample-bag --raw --no-truth
// --start 45 --frames 10): distorted image_raw with its calibration, the boom's tf and joints, no
// truth and no estimates. scripts/replay sees the raw images and puts image_proc's rectification
// in front of aar_stereo; --no-truth writes every estimate and no error tables. The poses are
// checked against the flight path the bag was rendered from (the simulator stamps path time +
// 1 s, its stamp_offset). Without --no-truth the replay fails, pointing to it.
TEST(Replay, RigBagRawImagesWithoutTruthGivesEstimates) {
  const std::string bag = kRoot + "/rosbags/sample_rig_contact.bag";
  const std::string out = ::testing::TempDir() + "/replay_rig";
  std::filesystem::remove_all(out);
  // Rate 0.1: on a loaded machine one frame in ten was once lost at 0.25 (the graph behind).
  const Result r = Sh(Replay(bag, out, 0.1) + " --no-truth");
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("the bag holds raw images (image_raw): image_proc rectifies them"),
            std::string::npos);
  EXPECT_NE(r.output.find("10 of 10 frames estimated, 10 with a pose; no truth"),
            std::string::npos);
  std::ifstream report(out + "/report.md");
  std::stringstream text;
  text << report.rdbuf();
  EXPECT_NE(text.str().find("estimates only, no error tables"), std::string::npos) << text.str();

  const aar_sim::FlightPath path =
      aar_sim::FlightPath::Load(kRoot + "/config/flight_paths/approach_default.csv");
  std::ifstream csv(out + "/dynamic/estimates.csv");
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line.rfind("stamp,valid,x_m,y_m,z_m,", 0), 0u) << line;
  int rows = 0;
  double worst_m = 0.0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 5u) << line;
    ASSERT_EQ(cells[1], "1") << "no pose: " << line;
    const Eigen::Vector3d estimate(std::stod(cells[2]), std::stod(cells[3]), std::stod(cells[4]));
    const Eigen::Vector3d truth = path.At(std::stod(cells[0]) - 1.0).position_m;
    worst_m = std::max(worst_m, (estimate - truth).norm());
    ++rows;
  }
  EXPECT_EQ(rows, 10);
  std::printf("[ rig ] worst position error %.4f m over %d frames\n", worst_m, rows);
  EXPECT_LT(worst_m, 0.035);  // 0.0252 m measured (raw + rectified, near contact)

  // With truth expected, every frame is unscored: a failure that names --no-truth.
  const Result scored = Sh(Replay(bag, out + "_scored", 0.1));
  EXPECT_EQ(scored.status, 1) << scored.output;
  EXPECT_NE(scored.output.find("--no-truth"), std::string::npos) << scored.output;
}

TEST(Replay, BrokenBagsAreNamedAndRefused) {
  const std::string dir = ::testing::TempDir() + "/replay_bad";
  std::filesystem::create_directories(dir);
  const std::string sample = kRoot + "/rosbags/sample_contact.bag";
  struct Case {
    std::string name, make, needle;
  };
  const Case cases[] = {
      {"no_right_info.bag",
       "rosbag filter " + sample + " " + dir +
           "/no_right_info.bag \"topic != '/stereo/right/camera_info'\"",
       "lacks /stereo/right/camera_info"},
      {"no_info.bag",
       "rosbag filter " + sample + " " + dir + "/no_info.bag \"not topic.endswith('camera_info')\"",
       "lacks /stereo/left/camera_info /stereo/right/camera_info"},
      {"truncated.bag", "head -c 3000000 " + sample + " > " + dir + "/truncated.bag",
       "is broken: ERROR bag unindexed"},
      {"garbage.bag", "printf 'not a bag' > " + dir + "/garbage.bag",
       "does not appear to be a bag file"},
      {"missing.bag", "true", "does not exist"},
  };
  for (const auto& c : cases) {
    const Result made = Sh(c.make);
    ASSERT_EQ(made.status, 0) << c.make << ": " << made.output;
    const Result r = Sh(Replay(dir + "/" + c.name, dir + "/out"));
    std::printf("[ replay ] %s: exit %d after %.1f s: %s", c.name.c_str(), r.status, r.seconds,
                r.output.c_str());
    EXPECT_EQ(r.status, 2) << c.name;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.name << ": " << r.output;
    EXPECT_LT(r.seconds, 60.0 * kScale) << c.name;
  }
}

// Headless rviz on the sample bag: the capture shows the removed boom points (magenta) and the
// reference points both cameras see (red), the colours config/rviz/aar.rviz gives them.
// A full disk (a 200 KB tmpfs: the logs fit, the 330 KB PNG does not): the capture names the file
// it could not write and ends, instead of leaving a truncated PNG and waiting out its 300 s.
TEST(Capture, AFullDiskIsNamedNotWaitedOut) {
  const std::string mount = ::testing::TempDir() + "/capture_full_disk";
  std::filesystem::create_directories(mount);
  Sh("umount " + mount + " 2>/dev/null");
  ASSERT_EQ(Sh("mount -t tmpfs -o size=200k tmpfs " + mount).status, 0) << "needs root";
  const Result r = Sh(Timeout(400) + kRoot + "/scripts/capture --no-build " + kRoot +
                      "/rosbags/sample_contact.bag --frames 6 --out " + mount + "/out");
  Sh("umount " + mount);
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("capture_frames: cannot write " + mount +
                          "/out/frame_006.png: [Errno 28] No space left on device"),
            std::string::npos);
  EXPECT_LT(r.seconds, 120.0 * kScale);  // measured 14 s; the capture's own limit is 300 s
}

// More frames than the bag holds is refused before anything starts (it waited out its own 3,117 s
// limit for frame 999 of 30); SIGINT (Ctrl-C) 20 s into a capture stops it and everything it
// started (it was deferred until roslaunch ended by itself: timeout keeps roslaunch in a
// process group of its own, which the signal never reached).
TEST(Capture, MoreFramesThanTheBagAndCtrlCAreAnsweredAtOnce) {
  const std::string out = ::testing::TempDir() + "/capture_interrupted";
  std::filesystem::remove_all(out);
  const std::string bag = kRoot + "/rosbags/sample_contact.bag";
  Result r = Sh(Timeout(60) + kRoot + "/scripts/capture --no-build " + bag +
                " --frames 6,999 --out " + out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(
      r.output.find("capture: --frames asks for frame 999, but '" + bag + "' holds 30 frames"),
      std::string::npos)
      << r.output;
  EXPECT_LT(r.seconds, 10.0 * kScale);  // measured 1.2 s
  EXPECT_FALSE(std::filesystem::exists(out));
  r = Sh("timeout -s INT 20 " + kRoot + "/scripts/capture --no-build " + bag +
         " --frames 15 --out " + out);
  EXPECT_NE(r.output.find("capture: SIGINT: stopped (roslaunch and its nodes ended"),
            std::string::npos)
      << r.output;
  EXPECT_LT(r.seconds, 60.0 * kScale);  // measured 26.6 s (20 s, then 1.6 s); before: 165 s
  const std::string mine = "[" + out.substr(0, 1) + "]" + out.substr(1);  // not the shell's own
  EXPECT_NE(Sh("pgrep -f '" + mine + "'").status, 0)
      << "left running: " << Sh("pgrep -af '" + mine + "'").output;
}

TEST(Capture, ScreenshotShowsTheConfiguredColours) {
  const std::string out = ::testing::TempDir() + "/capture_sample";
  std::filesystem::remove_all(out);
  const Result r = Sh(Timeout(400) + kRoot + "/scripts/capture --no-build " + kRoot +
                      "/rosbags/sample_contact.bag --frames 6 --out " + out);
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.status, 0);
  const std::string png = out + "/frame_006.png";
  ASSERT_TRUE(std::filesystem::exists(png));
  // Pixels of each colour in the 3D view (right of the image panels), counted by Pillow.
  const Result counts =
      Sh("/usr/bin/python3 -c \"from PIL import Image\n"
         "im = Image.open('" +
         png +
         "').convert('RGB'); w, h = im.size; px = im.load()\n"
         "m = r = 0\n"
         "for y in range(h):\n"
         "  for x in range(w // 4, w):\n"
         "    R, G, B = px[x, y]\n"
         "    m += R > 220 and G < 40 and B > 220\n"
         "    r += R > 220 and G < 40 and B < 40\n"
         "print(m, r)\"");
  ASSERT_EQ(counts.status, 0) << counts.output;
  int magenta = 0, red = 0;
  ASSERT_EQ(std::sscanf(counts.output.c_str(), "%d %d", &magenta, &red), 2) << counts.output;
  std::printf("[ capture ] %s: %d magenta (boom points), %d red (reference, both cameras)\n",
              png.c_str(), magenta, red);
  EXPECT_GT(magenta, 50);
  EXPECT_GT(red, 500);
}

}  // namespace
