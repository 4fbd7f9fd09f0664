// Two hosts (issues 15 and 31), built for real on this machine by scripts/two-hosts netns: two
// network namespaces of the test's own, joined by a veth pair on link-local addresses
// (169.254.X.1 and .2), the camera host (simulator at 2 Hz, the ROS master, eval against truth)
// in one and the perception host in the other, each behind its firewall (nftables, inside its
// namespace), the graph cut at the images and then at the cloud (stereo on the camera host).
// Poses come back across the link at the frame rate and with the accuracy of one machine, the
// cloud costing the link a tenth of the images; the perception host killed and started again
// resumes estimation while the camera host runs on; a perception host pointed at a master that is
// not there says which URI and waits; with the link down the run fails, in time. A third host on
// the link can neither register with the master, nor connect to a node, nor publish a pose; with
// --no-firewall the same attempts succeed and eval records forged poses. Nothing is left behind:
// the namespaces and every process of the run are gone at the end. Needs root (ip netns, nft),
// as CI's tests run. Bounds sit beyond the values measured here (in the comments;
// docs/MULTI_HOST.md), on a machine also running a sanitized suite (load 6 to 9).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

const std::string kRoot = aar_testing::WorkspaceRoot();

using Result = aar_testing::CommandResult;
const auto Sh = aar_testing::RunCommand;

std::string Read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

double Number(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) {
    ADD_FAILURE() << "not found: " << pattern << " in\n" << text;
    return -1.0;
  }
  return std::stod(m[1]);
}

// Kills every process in network namespace `ns` (ours: made by this test or its run) and
// removes it, if it exists.
void RemoveNamespace(const std::string& ns) {
  Sh("if ip netns list | awk '{print $1}' | grep -qx " + ns + "; then p=$(ip netns pids " + ns +
     "); [ -z \"$p\" ] || kill -9 $p; sleep 1; ip netns del " + ns + "; fi");
}

// One run of scripts/two-hosts netns under a name of this test's own; whatever the run leaves
// (it cannot, unless it was killed outright) is removed by the destructor, by namespace.
class TwoHosts {
 public:
  TwoHosts(const std::string& label, const std::string& options)
      : name("aarht" + std::to_string(::getpid() % 100000) + label),
        out(::testing::TempDir() + "/two_hosts_" + label) {
    std::filesystem::remove_all(out);
    // tracking: what these tests' bounds were measured with (two-hosts flies flight unless told).
    result = Sh("timeout -k 20 300 " + kRoot +
                "/scripts/two-hosts netns --no-build --experiment tracking --name " + name +
                " --out " + out + " " + options);
    std::printf("%s", result.output.c_str());
    summary = Read(out + "/summary.txt");
  }
  ~TwoHosts() {
    for (const char* side : {"-out", "-per", "-cam"}) RemoveNamespace(name + side);
  }
  // What the run left: its namespaces, and processes whose command line or environment names its
  // folder (each process it starts in a namespace has its ROS_HOME there).
  std::string LeftBehind() const {
    std::string left = Sh("ip netns list | awk '{print $1}' | grep -x -e " + name + "-cam -e " +
                          name + "-per -e " + name + "-out")
                           .output;
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string pid = entry.path().filename();
      if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
      std::string cmd = Read(entry.path() / "cmdline");
      std::replace(cmd.begin(), cmd.end(), '\0', ' ');
      if (cmd.find(out) != std::string::npos ||
          Read(entry.path() / "environ").find("ROS_HOME=" + out) != std::string::npos)
        left += "process " + pid + ": " + cmd + "\n";
    }
    return left;
  }

  const std::string name, out;
  Result result;
  std::string summary;
};

TEST(TwoHosts, PosesComeBackAcrossTheLinkAndARestartedPerceptionHostResumes) {
  TwoHosts run("k", "--phase 10");
  ASSERT_EQ(run.result.status, 0) << run.summary;
  const std::string& s = run.summary;
  EXPECT_NE(s.find("splits: images cloud; firewall on"), std::string::npos) << s;
  // Started before the camera host, the perception host waited, naming the master's URI.
  EXPECT_TRUE(std::regex_search(
      s,
      std::regex("waiting: perception host: no ROS master at http://169\\.254\\.[0-9]+\\.1:21311 "
                 "\\(Connection refused\\)")))
      << s;
  // Rate: every frame of the 2 Hz simulator answered with a pose across the link, with either
  // split (the firewall on).
  for (const char* phase : {"split images, phase 1", "phase 2", "split cloud, phase 1"}) {
    const std::string p = std::string("(^|\n)") + phase + ": ([0-9]+) frames in [0-9.]+ s, ";
    std::smatch m;
    ASSERT_TRUE(std::regex_search(s, m, std::regex(p))) << phase << "\n" << s;
    EXPECT_GE(std::stod(m[2]), 16.0) << phase;  // 20 at 2 Hz in 10 s (measured 20 and 21)
    // Measured 100 % in both phases of four runs, poses at 1.94 to 2.05 Hz.
    EXPECT_GE(Number(s, std::string(phase) + ": .* with a pose \\(([0-9.]+) %\\)"), 90.0) << phase;
    EXPECT_GE(Number(s, std::string(phase) + ": .* poses at ([0-9.]+) Hz"), 1.6) << phase;
  }
  // Accuracy of the poses that came back (region B to contact): as on one machine.
  for (const std::string split : {"images", "cloud"}) {
    const std::string a = "accuracy, split " + split + ": ";
    // Measured 61 (images: both phases and the restart) and 30 (cloud: its phase and stop).
    EXPECT_GE(Number(s, a + "([0-9]+) poses"), split == "images" ? 40.0 : 20.0) << split;
    EXPECT_LE(Number(s, a + ".*position error mean ([0-9.]+) m"), 0.05);    // 0.013 to 0.016 m
    EXPECT_LE(Number(s, a + ".*position error .* p95 ([0-9.]+) m"), 0.10);  // 0.026 to 0.037 m
    EXPECT_LE(Number(s, a + ".*angle error mean ([0-9.]+) deg"), 0.6);      // 0.214 to 0.218 deg
    EXPECT_TRUE(std::regex_search(s, std::regex(a + ".* 0 poses off by over 1 km"))) << s;
    // From a frame leaving the camera host to its pose back there (medians 0.046 to 0.061 s).
    EXPECT_LE(Number(s, "split " + split + ": link .* pose latency median ([0-9.]+) s"), 1.0);
  }
  // The perception host killed (every process, kill -9) and started again: poses resume, and the
  // camera host ran on (the same processes).
  EXPECT_GE(Number(s, "restart: perception host killed \\(([0-9]+) processes"), 4.0);
  // Measured 7.65 to 10.35 s (roslaunch, the nodelets, the receiver model, acquisition; load 7).
  EXPECT_LE(Number(s, "first pose ([0-9.]+) s after the restart"), 25.0);
  std::smatch kept;
  ASSERT_TRUE(
      std::regex_search(s, kept, std::regex("camera host processes kept: (\\d+) of (\\d+)")))
      << s;
  EXPECT_EQ(kept[1], kept[2]);
  EXPECT_GE(std::stoi(kept[2]), 5);  // roslaunch, rosmaster, rosout, sim, rsp, eval (6)
  // A master that is not there: named, waited for, no crash.
  EXPECT_TRUE(std::regex_search(
      s, std::regex("wrong master: .*http://169\\.254\\.[0-9]+\\.99:21311 was still waiting when "
                    "stopped after 12 s .*it said: perception host: no ROS master at "
                    "http://169\\.254\\.[0-9]+\\.99:21311 \\(")))
      << s;
  // Bandwidth: a 1280x960 mono8 pair with its camera infos; with the cloud split, the cloud.
  EXPECT_EQ(Number(s, "size: /stereo/left/image_rect [0-9]+ messages, mean ([0-9]+) bytes"),
            1228861.0);  // 1280 x 960 + header
  const double images = Number(s, "split images: link camera->perception ([0-9]+) bytes a frame");
  EXPECT_GE(images, 2.40e6);  // measured 2.44e6 to 2.58e6 (the pair, TCP/IP; 10 s windows vary)
  EXPECT_LE(images, 2.90e6);
  const double mbits = Number(s,
                              "split images: link camera->perception [0-9]+ bytes a frame, "
                              "([0-9.]+) Mbit/s at 2 Hz");
  EXPECT_GE(mbits, 35.0);  // 2 x 8 x 2.5 MB
  EXPECT_LE(mbits, 50.0);
  const double cloud = Number(s, "size: /stereo/points2 [0-9]+ messages, mean ([0-9]+) bytes");
  EXPECT_GE(cloud, 5.0e4);  // measured 1.0e5 on these ranges (it grows toward contact)
  const double cloud_link =
      Number(s, "split cloud: link camera->perception ([0-9]+) bytes a frame");
  // The cloud and tf, /clock, TCP/IP, so at least the cloud; but the link's bytes a frame are the
  // window's bytes over the run's mean frame rate, and the cloud's size a mean over the frames
  // its probe saw, not quite the same ones (it grows toward contact): a frame in about 20 (5 %).
  // Measured 1.006 times the cloud (40 s windows, MULTI_HOST.md) and 0.994 (10 s, a CI run).
  EXPECT_GE(cloud_link, 0.93 * cloud);
  EXPECT_LE(cloud_link, images / 10.0);  // measured 24 times less
  EXPECT_EQ(run.LeftBehind(), "");
}

// The link down (the perception host's end of the veth never comes up): no master, no pose. The
// run fails within its timeout, says so, and the perception host kept waiting, naming the URI.
TEST(TwoHosts, ALinkThatIsDownFailsTheRunInTimeAndLeavesNothing) {
  TwoHosts run("d", "--break-link --timeout 20");
  EXPECT_EQ(run.result.status, 1);
  EXPECT_LT(run.result.seconds, 120.0);  // measured 36.9 to 58.0 s (4, master start-up, 20, stop)
  EXPECT_NE(run.summary.find("FAIL: no pose came back across the link within 20 s"),
            std::string::npos)
      << run.summary;
  const std::string perception = Read(run.out + "/perception.log");
  EXPECT_TRUE(std::regex_search(
      perception,
      std::regex("perception host: no ROS master at http://169\\.254\\.[0-9]+\\.1:21311 \\(")))
      << perception;
  EXPECT_EQ(perception.find("starting the processing graph"), std::string::npos) << perception;
  EXPECT_EQ(run.LeftBehind(), "");
}

// A third host on the link (a third namespace on a bridge in the camera host's, 169.254.X.3)
// while poses flow with the cloud split. It reaches the camera host (a port that is not ROS's
// refuses it: the kernel's answer, not the firewall's), but its XML-RPC registerPublisher with
// the master, a connection to any port the camera host listens on, and a forged pose
// (x = 1e6 m) all fail: dropped, "timed out"; eval records no forged pose.
TEST(TwoHosts, AThirdHostOnTheLinkCannotRegisterConnectOrPublish) {
  TwoHosts run("i", "--split cloud --intruder --phase 8");
  ASSERT_EQ(run.result.status, 0) << run.summary;
  const std::string& s = run.summary;
  EXPECT_LT(run.result.seconds, 120.0);  // measured 39 s
  EXPECT_TRUE(std::regex_search(s, std::regex("intruder: TCP port 9 of 169\\.254\\.[0-9]+\\.1 "
                                              "\\(not a ROS port, nothing listens\\): Connection "
                                              "refused")))
      << s;
  EXPECT_TRUE(std::regex_search(
      s, std::regex("intruder: registerPublisher /aar/pose_estimate with the master "
                    "http://169\\.254\\.[0-9]+\\.1:21311: refused: timed out after 3 s")))
      << s;
  std::smatch scan;
  ASSERT_TRUE(std::regex_search(
      s, scan,
      std::regex("intruder: the camera host's listening ports \\([0-9,]+\\): 0 of ([0-9]+) accept "
                 "a connection; the others: timed out after 3 s\n")))
      << s;
  EXPECT_GE(std::stoi(scan[1]), 6);  // the master, rosout, sim, rsp, stereo's manager, eval...
  ASSERT_TRUE(std::regex_search(
      s, scan,
      std::regex("intruder: the perception host's listening ports \\([0-9,]+\\): 0 of ([0-9]+) "
                 "accept a connection; the others: timed out after 3 s\n")))
      << s;
  EXPECT_GE(std::stoi(scan[1]), 4);  // roslaunch, the manager, occlusion, registration...
  EXPECT_TRUE(std::regex_search(
      s, std::regex("intruder: publish /aar/pose_estimate: refused: no node came up in 8 s")))
      << s;
  // Every frame still had its pose, none forged.
  EXPECT_GE(Number(s, "split cloud, phase 1: .* with a pose \\(([0-9.]+) %\\)"), 90.0);
  EXPECT_GE(Number(s, "accuracy, split cloud: ([0-9]+) poses"), 20.0);
  EXPECT_TRUE(
      std::regex_search(s, std::regex("accuracy, split cloud: .* 0 poses off by over 1 km")))
      << s;
  EXPECT_EQ(run.LeftBehind(), "");
}

// The same intruder with --no-firewall: what the firewall stops. It registers with the master,
// connects to every port and publishes forged poses (copies of the real ones at x = 1e6 m,
// arriving after them). Before eval took estimates only from one publisher, those were what eval
// recorded for 14 of the frames; now eval names them and leaves them out.
TEST(TwoHosts, WithoutTheFirewallTheIntruderRegistersAndPublishesAndEvalIgnoresIt) {
  TwoHosts run("n", "--split cloud --intruder --no-firewall --phase 8");
  ASSERT_EQ(run.result.status, 0) << run.summary;
  const std::string& s = run.summary;
  EXPECT_LT(run.result.seconds, 120.0);  // measured 33 s
  EXPECT_NE(s.find("no firewall (--no-firewall)"), std::string::npos) << s;
  EXPECT_TRUE(std::regex_search(
      s, std::regex("intruder: registerPublisher /aar/pose_estimate with the master "
                    "http://169\\.254\\.[0-9]+\\.1:21311: ACCEPTED \\(code 1\\)")))
      << s;
  std::smatch scan;
  ASSERT_TRUE(std::regex_search(
      s, scan,
      std::regex("intruder: the camera host's listening ports \\([0-9,]+\\): ([0-9]+) of ([0-9]+) "
                 "accept a connection")))
      << s;
  EXPECT_EQ(scan[1], scan[2]);
  ASSERT_TRUE(std::regex_search(s, scan,
                                std::regex("intruder: the perception host's listening ports "
                                           "\\([0-9,]+\\): ([0-9]+) of ([0-9]+) accept")))
      << s;
  EXPECT_EQ(scan[1], scan[2]);
  EXPECT_GE(Number(s,
                   "intruder: publish /aar/pose_estimate: ACCEPTED: ([0-9]+) poses at x = "
                   "1e\\+06 m published"),
            5.0);  // measured 15 in 8 s
  // Past the firewall, eval still takes estimates only from the registration it heard first
  // (the frame ledger's caller-id check): the forged poses are named and left out.
  EXPECT_EQ(Number(s, "accuracy, split cloud: .* ([0-9]+) poses off by over 1 km"), 0.0);
  const std::string camera_log = Read(run.out + "/camera-cloud.log");
  EXPECT_TRUE(std::regex_search(camera_log, std::regex("from /intruder_[0-9_]+, not from the "
                                                       "registration \\(/aar_manager\\): "
                                                       "ignored")))
      << camera_log.substr(camera_log.size() > 4000 ? camera_log.size() - 4000 : 0);
  EXPECT_EQ(run.LeftBehind(), "");
}

// On a real host (here a namespace of the test's own, with a veth end on a link-local address)
// the camera host's script installs its table while it runs and removes it when stopped by
// SIGTERM (also SIGINT, as from a terminal), with everything it started.
TEST(TwoHosts, TheFirewallIsInstalledWhileAHostRunsAndRemovedWhenItStops) {
  const std::string ns = "aarht" + std::to_string(::getpid() % 100000) + "f";
  const std::string dev = ns + "a";
  RemoveNamespace(ns);
  ASSERT_EQ(Sh("ip netns add " + ns + " && ip -n " + ns + " link set lo up && ip link add " + dev +
               " type veth peer name " + ns + "b && ip link set " + dev + " netns " + ns +
               " && ip -n " + ns + " addr add 169.254.7.1/16 dev " + dev + " && ip -n " + ns +
               " link set " + dev + " up")
                .status,
            0);
  const std::string out = ::testing::TempDir() + "/two_hosts_f";
  const Result r =
      Sh("ip netns exec " + ns + " env --default-signal=INT " + kRoot +
         "/scripts/two-hosts camera --ip 169.254.7.1 --peer 169.254.7.2 --out " + out + " > " +
         out + ".log 2>&1 & pid=$!; for i in $(seq 1 60); do sleep 0.5; ip netns exec " + ns +
         " nft list table inet aar_two_hosts > " + out +
         ".table 2>&1 && break; done; sleep 3; "
         "kill -TERM $pid; wait $pid; echo \"status $?\"; ip netns exec " +
         ns + " nft list tables; echo \"left: $(ip netns pids " + ns + " | wc -l)\"");
  const std::string table = Read(out + ".table");
  RemoveNamespace(ns);
  Sh("ip link del " + ns + "b 2>/dev/null");
  EXPECT_NE(table.find("iifname \"" + dev +
                       "\" ip saddr 169.254.7.2 meta l4proto { tcp, udp } th dport { 21311, "),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("drop comment \"ROS ports: 169.254.7.2 on " + dev + " only\""),
            std::string::npos)
      << table;
  // Stopped: no table left, no process left in the namespace.
  EXPECT_EQ(r.output.find("table inet aar_two_hosts"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("left: 0"), std::string::npos) << r.output;
  EXPECT_LT(r.seconds, 60.0);
}

TEST(TwoHosts, BadArgumentsAreNamedAndRefused) {
  const std::pair<std::string, std::string> cases[] = {
      {"", "say which: camera, perception or netns"},
      {"hosts", "unknown mode 'hosts'"},
      {"camera", "camera: --ip ADDR is needed"},
      {"camera --ip 300.1.1.1", "camera: --ip takes an IPv4 address, not '300.1.1.1'"},
      {"camera --ip 169.254.77.77", "camera: --ip 169.254.77.77 is not an address of this host"},
      {"camera --ip 127.0.0.1 --port 80", "--port takes a port from 1024 to 65535, not '80'"},
      {"camera --ip 127.0.0.1 --rate 0", "--rate takes frames per second (above 0, at most 60)"},
      {"camera --ip 127.0.0.1 --bag /nonexistent.bag", "--bag '/nonexistent.bag' does not exist"},
      {"perception --ip 127.0.0.1", "perception: --master URI is needed"},
      {"perception --master 169.254.1.1:21311 --ip 127.0.0.1",
       "--master takes http://HOST:PORT (the camera host's master), not '169.254.1.1:21311'"},
      {"perception --master http://169.254.1.1:21311", "perception: --ip ADDR is needed"},
      {"perception --master http://169.254.1.1:21311 --ip 127.0.0.1 --experiment nonsense",
       "no experiment 'nonsense' in config/experiments/"},
      {"netns --rate 100", "--rate takes frames per second from 0.5 to 30, not '100'"},
      {"netns --phase 1", "--phase takes whole seconds (at least 4), not '1'"},
      {"netns --name Bad-Name", "--name takes 2 to 13 lower-case letters and digits"},
      {"netns --timeout", "--timeout needs a value"},
      {"netns --nonsense", "netns: unknown argument '--nonsense'"},
      {"netns --split half", "netns: --split takes images, cloud or both, not 'half'"},
      {"camera --ip 127.0.0.1", "camera: --peer ADDR is needed (the other host's address"},
      {"camera --ip 127.0.0.1 --peer 300.1.1.1", "--peer takes an IPv4 address, not '300.1.1.1'"},
      {"camera --ip 127.0.0.1 --peer 127.0.0.1", "--peer 127.0.0.1 is this host's --ip"},
      {"camera --ip 127.0.0.1 --split pixels",
       "camera: --split takes images or cloud (where the graph is cut), not 'pixels'"},
      {"perception --master http://camera:21311 --ip 127.0.0.1",
       "perception: --peer ADDR is needed"},
      {"perception --master http://169.254.1.1:21311 --ip 127.0.0.1 --split x",
       "perception: --split takes images or cloud"},
  };
  for (const auto& [options, needle] : cases) {
    const Result r = Sh(kRoot + "/scripts/two-hosts " + options);
    EXPECT_EQ(r.status, 2) << options << ": " << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << options << ": " << r.output;
  }
}

// Given a master it cannot reach and --give-up, the perception host names the URI and the reason
// and ends with status 1 (without --give-up it waits for ever, as the netns run shows). In a
// namespace of the test's own with only its loopback: nothing leaves it.
TEST(TwoHosts, PerceptionHostGivesUpOnAnUnreachableMasterWhenAskedTo) {
  const std::string ns = "aarht" + std::to_string(::getpid() % 100000) + "g";
  RemoveNamespace(ns);
  ASSERT_EQ(Sh("ip netns add " + ns + " && ip -n " + ns + " link set lo up").status, 0);
  const Result r = Sh("ip netns exec " + ns + " " + kRoot +
                      "/scripts/two-hosts perception --master http://169.254.1.1:21311 --ip "
                      "127.0.0.1 --give-up 4");
  RemoveNamespace(ns);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("perception host: no ROS master at http://169.254.1.1:21311 (Network "
                          "is unreachable)"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output, std::regex("gave up after [0-9]+ s: no ROS master at http://169.254.1.1:21311")))
      << r.output;
  EXPECT_LT(r.seconds, 30.0);
}

}  // namespace
