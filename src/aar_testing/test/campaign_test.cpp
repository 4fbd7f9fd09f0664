// The campaign driver (scripts/campaign/, behind scripts/run: one path, --suite, --worlds):
// a suite through a real Slurm (munged, slurmctld and slurmd started on this machine) gives the
// local engine's suite.md to the last digit; a Slurm task cancelled mid-run is named and then
// resumed; an interrupted local campaign says how to resume and resumes without flying again
// what it finished; bad engine input is named before anything starts. Needs root (Slurm's
// daemons); every command is bounded by `timeout`.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

// scripts/run with the workspace as built (no setup or build), bounded in time.
std::string ScriptsRun(const std::string& args, int seconds = 900) {
  return "timeout -s INT --preserve-status " + std::to_string(seconds) + " " +
         aar_testing::WorkspaceRoot() + "/scripts/run " + args + " --no-build";
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool Exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

long ModifiedNs(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return -1;
  return st.st_mtim.tv_sec * 1000000000L + st.st_mtim.tv_nsec;
}

// suite.md without its Run section (date, wall time, folder and engine differ by design).
std::string Results(const std::string& dir) {
  const std::string md = Read(dir + "/suite.md");
  const size_t at = md.find("## Approaches");
  return at == std::string::npos ? "" : md.substr(at);
}

// Waits (polling each second, at most `seconds`) until `path` exists.
bool WaitFor(const std::string& path, int seconds) {
  return aar_testing::RunCommand("for i in $(seq 1 " + std::to_string(seconds) + "); do [ -e '" +
                                 path + "' ] && exit 0; sleep 1; done; exit 1")
             .status == 0;
}

// The 1 x 2 suite both engines fly (two runs: one a node on two nodes): at 1.25 Hz, about 65
// frames a run (2 Hz: 100; what these tests check does not need more; it was 2 x 2 until the
// suite's time was cut). Not below 1 Hz: frames more than stereo's max_stamp_lead (1 s)
// apart are dropped as "ahead" when a pair comes before its /clock (seen once at 0.5 Hz).
const char* kSuite = "--suite 1 --experiments naive,dynamic --rate 1.25";

TEST(Campaign, BadEngineInputIsNamedBeforeAnythingStarts) {
  const std::string out = "/tmp/aar_campaign_bad";
  aar_testing::RunCommand("rm -rf " + out);
  const struct {
    std::string env, args, needle;
  } cases[] = {
      {"", "--suite 1 --partition x", "--partition and --no-wait are for --engine slurm"},
      {"", "--suite 1 --engine slurm --cpus-per-task 0",
       "--cpus-per-task takes a whole number of CPUs, not '0'"},
      {"", "--resume /nonexistent_campaign", "'/nonexistent_campaign' holds no campaign"},
      {"", "--resume /tmp --experiments naive", "--resume flies the campaign's own plan"},
      {"env -u SLURM_CONF", "--suite 1 --engine slurm --no-wait",
       "--no-wait needs a cluster that outlives the driver"},
      // A cluster configured but its client missing: the package is named.
      {"env SLURM_CONF=/nonexistent.conf AAR_SLURM_BIN=/nonexistent", "--suite 1 --engine slurm",
       "needs Slurm's sbatch, which is not on /nonexistent (Debian package slurm-client"},
  };
  for (const auto& c : cases) {
    if (c.env == "env -u SLURM_CONF" && Exists("/etc/slurm/slurm.conf")) continue;
    const bool resume = c.args.rfind("--resume", 0) == 0;  // its folder is the campaign's
    const auto r = aar_testing::RunCommand(
        c.env + " " + ScriptsRun(c.args + (resume ? "" : " --out " + out), 60));
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
    EXPECT_FALSE(Exists(out)) << c.args << ": the refused campaign left " << out;
  }
}

TEST(Campaign, AnInterruptedCampaignSaysHowToResumeAndResumes) {
  const std::string out = "/tmp/aar_campaign_interrupted";
  aar_testing::RunCommand("rm -rf " + out);
  // Interrupted (SIGINT, as Ctrl-C) once the first of its two runs is done, the second flying.
  const std::string first = out + "/approaches/01/naive/run.json";
  auto r = aar_testing::RunCommand(
      ScriptsRun("--suite 1 --experiments naive,dynamic --rate 1.25 --jobs 1 --out " + out) +
      " & pid=$!; for i in $(seq 1 300); do [ -e " + first +
      " ] && break; sleep 1; done; sleep 3; kill -INT $pid; wait $pid");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("fly what is missing with: scripts/run --resume " + out),
            std::string::npos)
      << r.output;
  std::string md = Read(out + "/suite.md");
  EXPECT_NE(md.find("**INCOMPLETE:** missing or short: 01/dynamic"), std::string::npos) << md;
  EXPECT_NE(md.find("failed or missing runs (1): approaches/01/dynamic"), std::string::npos) << md;
  EXPECT_NE(md.find("interrupted"), std::string::npos) << md;

  // A new campaign may not write into it.
  r = aar_testing::RunCommand(
      ScriptsRun("--suite 1 --experiments naive --rate 1.25 --out " + out, 60));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("holds a campaign already: resume it with scripts/run --resume"),
            std::string::npos)
      << r.output;

  const std::string kept = out + "/approaches/01/naive/frames.csv";
  const long before = ModifiedNs(kept);
  r = aar_testing::RunCommand(ScriptsRun("--resume " + out));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("1 of 2 runs done already; flying the other 1"), std::string::npos)
      << r.output;
  EXPECT_EQ(ModifiedNs(kept), before) << "the finished run was flown again";
  md = Read(out + "/suite.md");
  EXPECT_EQ(md.find("INCOMPLETE"), std::string::npos) << md;
  EXPECT_NE(md.find("| dynamic | 1 |"), std::string::npos) << md;
}

// A run whose processing manager dies (kill -9) once it is flying is flown again, and says so:
// on the console, in run.txt and in the report, with the failed attempt's log kept beside it.
TEST(Campaign, ARunFlownAgainAfterACrashIsNamedWithItsLog) {
  const std::string out = "/tmp/aar_campaign_crash", run = out + "/approaches/01/naive";
  aar_testing::RunCommand("rm -rf " + out);
  // The manager: the child of the run's roslaunch (launch.log is written at the end, so the
  // test watches the processes), killed 5 s after it started, mid-flight (the run: 1 Hz, about
  // 55 frames, 16 s).
  const std::string manager =
      "for p in $(pgrep -f '^/usr/bin/python3 /usr/bin/roslaunch .*"
      "output_dir:=" +
      run +
      " '); do pgrep -P $p -f '^/usr/lib/nodelet/nodelet manager'; "
      "done | head -n 1";
  auto r = aar_testing::RunCommand(
      ScriptsRun("--suite 1 --experiments naive --rate 1 --jobs 1 --out " + out) +
      " & pid=$!; for i in $(seq 1 300); do m=$(" + manager +
      "); [ -n \"$m\" ] && break; sleep 0.5; done; sleep 5; kill -9 $m; wait $pid");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("ok (on its retry; attempt 1: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(", its log launch.attempt1.log)"), std::string::npos) << r.output;
  const std::string said =
      "runs that failed and were flown again (1):\n  approaches/01/naive: "
      "attempt 1: ";
  EXPECT_NE(Read(out + "/run.txt").find(said), std::string::npos) << Read(out + "/run.txt");
  EXPECT_NE(Read(out + "/suite.md").find(said), std::string::npos) << Read(out + "/suite.md");
  EXPECT_NE(Read(run + "/launch.attempt1.log").find("process has died"), std::string::npos)
      << "the crashed attempt's log is gone: " << Read(run + "/launch.attempt1.log");
  EXPECT_NE(Read(run + "/launch.log").find("eval: wrote"), std::string::npos);
}

// Ctrl-C while the reports are written (rviz captures of the sample bag, about 30 s): the
// capture stops with everything it started, the driver says how to get the reports and exits
// 130, no traceback (it was a KeyboardInterrupt traceback, and roslaunch, the master, the
// manager, the players and capture_frames.py ran on). A run with a missing frame skips them.
TEST(Campaign, CtrlCWhileTheReportsAreWrittenLeavesNothingRunning) {
  const std::string out = "/tmp/aar_campaign_reports_interrupted";
  aar_testing::RunCommand("rm -rf " + out);
  auto r = aar_testing::RunCommand(ScriptsRun("--frames 20 --experiments naive --out " + out));
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_NE(r.output.find("wrote " + out + "/report.md"), std::string::npos) << r.output;
  // A normal end reads as one: the sim says it is done and roslaunch no "REQUIRED process [sim-3]
  // has died!" (end_launch_on_exit.py ends the launch), nor the capture's for its capture node.
  const std::string log = Read(out + "/naive/launch.log");
  EXPECT_NE(log.find("sim: flight path done, 20 frames"), std::string::npos) << log;
  EXPECT_EQ(log.find("has died"), std::string::npos) << log;
  EXPECT_EQ(Read(out + "/captures/launch.log").find("has died"), std::string::npos);
  // --resume of a finished campaign writes the reports again; SIGINT 12 s in, mid-capture.
  r = aar_testing::RunCommand("timeout -s INT 12 " + aar_testing::WorkspaceRoot() +
                              "/scripts/run --resume " + out + " --no-build");
  EXPECT_EQ(r.status, 124) << r.output;  // timeout's own: it sent the signal
  EXPECT_NE(r.output.find("interrupted while writing the reports (the step running was "
                          "stopped); scripts/run --resume " +
                          out + " writes them"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("Traceback"), std::string::npos) << r.output;
  EXPECT_LT(r.seconds, 60.0) << r.output;  // 12 s, then the capture's stop
  const std::string mine = "[" + out.substr(0, 1) + "]" + out.substr(1);  // not the shell's own
  EXPECT_NE(aar_testing::RunCommand("pgrep -f '" + mine + "'").status, 0)
      << "left running: " << aar_testing::RunCommand("pgrep -af '" + mine + "'").output;
}

// A full disk, at three points of a run (the configuration's copy, the run's own files, the
// reports): each write that failed is named with its file and the disk's complaint, never a
// traceback, never a "wrote" for it, never a truncated record, and the exit code is 1. A tmpfs
// of each size, mounted here (needs root), unmounted at the end.
TEST(Campaign, AFullDiskIsNamedAtEveryStepWithoutATraceback) {
  const std::string disk = "/tmp/aar_campaign_full_disk";
  for (const std::string size : {"16k", "60k", "160k"}) {
    aar_testing::RunCommand("umount " + disk + " 2>/dev/null; mkdir -p " + disk);
    ASSERT_EQ(aar_testing::RunCommand("mount -t tmpfs -o size=" + size + " tmpfs " + disk).status,
              0)
        << "needs root to mount a tmpfs";
    const std::string out = disk + "/run";
    const auto r =
        aar_testing::RunCommand(ScriptsRun("--frames 10 --experiments naive --out " + out, 300));
    const std::string json = Read(out + "/naive/run.json");
    aar_testing::RunCommand("umount " + disk);
    EXPECT_EQ(r.status, 1) << size << ": " << r.output;
    EXPECT_NE(r.output.find(out + "/"), std::string::npos) << size << ": " << r.output;
    EXPECT_NE(r.output.find("No space left on device"), std::string::npos)
        << size << ": " << r.output;
    EXPECT_EQ(r.output.find("Traceback"), std::string::npos) << size << ": " << r.output;
    if (r.output.find(out + "/report.md: write failed") != std::string::npos)
      EXPECT_EQ(r.output.find("wrote " + out + "/report.md"), std::string::npos) << r.output;
    if (!json.empty()) EXPECT_EQ(json.back(), '}') << size << ": a truncated run.json: " << json;
    if (size == "16k")  // nothing flown: said, with what to do (a --resume has nothing to resume)
      EXPECT_NE(r.output.find("nothing was flown: make room, remove " + out + " and run again"),
                std::string::npos)
          << r.output;
  }
}

// kSuite flown by the local engine into kLocal, once in this process; its output.
const char* kLocal = "/tmp/aar_campaign_local";
const aar_testing::CommandResult& LocalSuite() {
  static const aar_testing::CommandResult r = [] {
    aar_testing::RunCommand(std::string("rm -rf ") + kLocal);
    return aar_testing::RunCommand(ScriptsRun(std::string(kSuite) + " --out " + kLocal));
  }();
  return r;
}

TEST(Campaign, ASuiteThroughSlurmEqualsTheLocalOne) {
  const std::string local = kLocal, slurm = "/tmp/aar_campaign_slurm";
  aar_testing::RunCommand("rm -rf " + slurm);
  auto r = LocalSuite();
  ASSERT_EQ(r.status, 0) << r.output;
  // Progress as plain lines (not a terminal): runs and frames done of all, rate, time to go.
  const std::regex progress(
      R"(progress: 2/2 runs, (\d+)/\1 frames, [0-9.]+ frames/s, \d+:\d\d:\d\d so far, )"
      R"(0:00:00 to go)");
  EXPECT_TRUE(std::regex_search(r.output, progress)) << r.output;
  EXPECT_NE(r.output.find("progress: 1/2 runs, "), std::string::npos) << r.output;
  // Each run's CPU time (its launch and every node, from wait4): more than none.
  std::smatch cpu;
  const std::string run_json = Read(local + "/approaches/01/naive/run.json");
  ASSERT_TRUE(std::regex_search(run_json, cpu, std::regex(R"("cpu_seconds": ([0-9.]+))")))
      << run_json;
  EXPECT_GT(std::stod(cpu[1]), 1.0) << run_json;
  // No cluster configured: the driver brings a single-node one up, and stops it at the end.
  r = aar_testing::RunCommand("env -u SLURM_CONF " +
                              ScriptsRun(std::string(kSuite) + " --engine slurm --out " + slurm));
  ASSERT_EQ(r.status, 0) << r.output;
  if (!Exists("/etc/slurm/slurm.conf")) {
    EXPECT_NE(r.output.find("bringing up a single-node one"), std::string::npos) << r.output;
  }
  EXPECT_NE(r.output.find("2 runs submitted to Slurm as job array"), std::string::npos) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, progress)) << "the queue's progress: " << r.output;
  for (int task = 0; task < 2; ++task) {
    const std::string log =
        aar_testing::RunCommand("cat " + slurm + "/slurm/*-task-" + std::to_string(task) + ".log")
            .output;
    EXPECT_NE(log.find(" frames, ok"), std::string::npos) << "task " << task << ": " << log;
  }
  EXPECT_NE(Read(slurm + "/run.txt").find("(slurm, job array"), std::string::npos);
  const std::string expected = Results(local);
  ASSERT_NE(expected.find("| dynamic | 1 |"), std::string::npos) << Read(local + "/suite.md");
  EXPECT_EQ(Results(slurm), expected);
  // The cluster it brought up is gone, and its folder with it.
  EXPECT_NE(aar_testing::RunCommand("pgrep -f 'slurmctld -f /tmp/aar-slurm[.]'").status, 0);
  std::smatch state;
  if (std::regex_search(r.output, state, std::regex(R"(SLURM_CONF=(/tmp/aar-slurm\.\w+)/)"))) {
    EXPECT_FALSE(Exists(state[1])) << state[1];
  }
}

// A single-node cluster of the test's own, stopped however the test ends. MaxArraySize 1: each
// run is an array of its own, as runs beyond MaxArraySize are on a real cluster.
struct Cluster {
  const std::string dir = "/tmp/aar_campaign_cluster";
  aar_testing::CommandResult up;
  Cluster() {
    aar_testing::RunCommand("rm -rf " + dir);
    up = aar_testing::RunCommand("AAR_SLURM_MAX_ARRAY_SIZE=1 timeout 300 " +
                                 aar_testing::WorkspaceRoot() + "/scripts/slurm-local up " + dir);
  }
  ~Cluster() {
    aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/slurm-local down " + dir);
  }
};

// scripts/slurm-local's wrong arguments: named, exit 2, nothing started.
TEST(Campaign, SlurmLocalNamesBadArguments) {
  const std::string script = aar_testing::WorkspaceRoot() + "/scripts/slurm-local ";
  const struct {
    std::string args, needle;
  } cases[] = {
      {"up /tmp/aar_slurm_bad --nodes 0", "--nodes needs a count from 1 to 99, not '0'"},
      {"up /tmp/aar_slurm_bad --node 2", "up: unknown option '--node'"},
      {"down /tmp", "'/tmp' is no cluster of scripts/slurm-local"},
      {"down /tmp --kep", "down: unknown option '--kep'"},
      {"kill /tmp 1", "'/tmp' is no multi-node cluster of scripts/slurm-local"},
      {"start", "scripts/slurm-local up [DIR] [--nodes N]"},
  };
  for (const auto& c : cases) {
    const auto r = aar_testing::RunCommand("timeout 60 " + script + c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
  }
  EXPECT_FALSE(Exists("/tmp/aar_slurm_bad"));
}

// Two compute nodes on this machine: each slurmd in network and UTS namespaces of its own
// (aar-node1 and 2, 169.254.X.11 and .12, the controller on .1), munge's key and the workspace
// shared. Node 2 is killed (every process, kill -9: a power cut) while it flies a run: Slurm marks
// it down and requeues that run, which node 1 flies; suite.md equals the local engine's, no run
// lost or counted twice.
TEST(Campaign, ASuiteOnTwoNodesLosesANodeAndNothingElse) {
  const std::string dir = "/tmp/aar_campaign_nodes_cluster", out = "/tmp/aar_campaign_nodes";
  const std::string script = aar_testing::WorkspaceRoot() + "/scripts/slurm-local ";
  aar_testing::RunCommand("rm -rf " + out + " " + dir);
  struct Down {
    std::string command;
    ~Down() { aar_testing::RunCommand(command); }
  } down{script + "down " + dir};
  auto r = aar_testing::RunCommand("timeout 300 " + script + "up " + dir + " --nodes 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::regex_search(
      r.output, std::regex(R"(up: nodes aar-node\[1-2\] \(169\.254\.[0-9]+\.11 on, 1 CPUs each)")))
      << r.output;
  const std::string env = "env SLURM_CONF=" + dir + "/slurm.conf ";
  r = aar_testing::RunCommand(
      env + ScriptsRun(std::string(kSuite) + " --engine slurm --no-wait --out " + out, 60));
  ASSERT_EQ(r.status, 0) << r.output;
  // Tasks 0 and 1 fly at once, one a node; 3 s into both (a run there: about 20 s), node 2 dies.
  ASSERT_TRUE(WaitFor(out + "/approaches/01/naive/frames.csv", 120));
  ASSERT_TRUE(WaitFor(out + "/approaches/01/dynamic/frames.csv", 120));
  aar_testing::RunCommand("sleep 3");
  const std::string on_node2 =
      aar_testing::RunCommand("grep -l 'on node aar-node2$' " + out + "/slurm/*-task-*.log").output;
  ASSERT_EQ(on_node2.find('\n'), on_node2.size() - 1) << "one task on node 2: " << on_node2;
  r = aar_testing::RunCommand(script + "kill " + dir + " 2");
  ASSERT_EQ(r.status, 0) << r.output;
  // Down within 15 s and some; requeued, then held by Slurm for cred_expire (30 s on
  // scripts/slurm-local's clusters) before it flies again.
  ASSERT_TRUE(WaitFor(out + "/slurm/merge.json", 480)) << Read(dir + "/log/slurmctld.log");
  EXPECT_NE(Read(out + "/slurm/merge.json").find("\"missing\": []"), std::string::npos)
      << Read(out + "/slurm/merge.json");
  EXPECT_EQ(aar_testing::RunCommand(env + "sinfo -h -n aar-node2 -o %T").output.substr(0, 4),
            "down");
  // The lost task is named where it ran again, with its lost attempt's log kept.
  const std::string task = Read(on_node2.substr(0, on_node2.size() - 1));
  std::smatch run;
  ASSERT_TRUE(std::regex_search(task, run, std::regex(R"(run [0-9]: (approaches/0[12]/\w+) on)")))
      << task;
  EXPECT_TRUE(std::regex_search(
      task, std::regex(run[1].str() + " on node aar-node1 \\(requeued 1 time\\(s\\)")))
      << task;
  EXPECT_NE(task.find(run[1].str() + ": the lost attempt's log kept as slurm/"), std::string::npos)
      << task;
  const std::string json = Read(out + "/" + run[1].str() + "/run.json");
  EXPECT_NE(json.find("\"slurm_restarts\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"node\": \"aar-node1\""), std::string::npos) << json;
  EXPECT_NE(Read(out + "/run.txt").find(run[1].str() + ": requeued by Slurm 1 time(s)"),
            std::string::npos)
      << Read(out + "/run.txt");
  const auto& local = LocalSuite();
  ASSERT_EQ(local.status, 0) << local.output;
  const std::string expected = Results(kLocal);
  ASSERT_NE(expected.find("| dynamic | 1 |"), std::string::npos)
      << Read(kLocal + std::string("/suite.md"));
  EXPECT_EQ(Results(out), expected);
}

TEST(Campaign, ACancelledSlurmTaskIsNamedThenResumed) {
  const std::string out = "/tmp/aar_campaign_cancelled";
  aar_testing::RunCommand("rm -rf " + out);
  const Cluster cluster;
  ASSERT_EQ(cluster.up.status, 0) << cluster.up.output;
  aar_testing::CommandResult r;
  const std::string env = "env SLURM_CONF=/tmp/aar_campaign_cluster/slurm.conf ";

  r = aar_testing::RunCommand(
      env + ScriptsRun("--suite 1 --engine slurm --partition nosuch --out " + out, 60));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("no partition 'nosuch' on this cluster (partitions: aar)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(Exists(out));

  r = aar_testing::RunCommand(
      env +
      ScriptsRun(
          "--suite 1 --experiments naive,dynamic --rate 1.25 --engine slurm --no-wait --out " + out,
          60));
  ASSERT_EQ(r.status, 0) << r.output;
  // Task 0 (approach 01, naive) cancelled once it flies.
  EXPECT_TRUE(WaitFor(out + "/approaches/01/naive/launch.log", 120));
  r = aar_testing::RunCommand(env + "sh -c 'sleep 3; scancel $(python3 -c \"import json; print(" +
                              "json.load(open(\\\"" + out +
                              "/slurm/jobs.json\\\"))[\\\"arrays\\\"][0])\")_0'");
  EXPECT_EQ(r.status, 0) << r.output;
  ASSERT_TRUE(WaitFor(out + "/slurm/merge.json", 300));
  const std::string jobs = Read(out + "/slurm/jobs.json");
  EXPECT_NE(jobs.find("\"array_size\": 1"), std::string::npos) << jobs;
  EXPECT_TRUE(std::regex_search(jobs, std::regex(R"("arrays": \["[0-9]+", "[0-9]+"\])")))
      << "two arrays: " << jobs;
  EXPECT_NE(Read(out + "/slurm/merge.json").find("\"missing\": [\"approaches/01/naive\"]"),
            std::string::npos)
      << Read(out + "/slurm/merge.json");
  const std::string task0 = aar_testing::RunCommand("cat " + out + "/slurm/*-task-0.log").output;
  EXPECT_NE(task0.find("(cancelled)"), std::string::npos) << task0;
  std::string md = Read(out + "/suite.md");
  EXPECT_NE(md.find("**INCOMPLETE:** missing or short: 01/naive"), std::string::npos) << md;

  r = aar_testing::RunCommand(env + ScriptsRun("--resume " + out + " --engine slurm"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("1 of 2 runs done already"), std::string::npos) << r.output;
  md = Read(out + "/suite.md");
  EXPECT_EQ(md.find("INCOMPLETE"), std::string::npos) << md;
}

}  // namespace
