// scripts/run --suite refuses bad arguments with a message naming them and a non-zero exit,
// before anything is set up, built or flown (the campaign driver, scripts/campaign/, checks them);
// a suite with --receiver generates that receiver's approaches, gives it to its runs, records it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

aar_testing::CommandResult Suite(const std::string& args) {
  return aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/run --no-build " + args +
                                 " --out /tmp/aar_suite_script_test");
}

TEST(SuiteScript, BadArgumentsAreNamedAndRefused) {
  const struct {
    std::string args, needle;
  } cases[] = {
      {"--suite 0", "--suite takes a number of approaches of at least 1, not '0'"},
      {"--suite -3", "--suite takes a number of approaches of at least 1, not '-3'"},
      {"--suite 2 --seed abc", "--seed takes a whole number (at most 12 digits), not 'abc'"},
      {"--suite 2 --jobs 999", "(this machine's cores), not '999'"},
      {"--suite 2 --jobs 0", "(this machine's cores), not '0'"},
      {"--suite 2 --experiments naive,nonsense", "no experiment 'nonsense' in config/experiments/"},
      {"--suite 2 --experiments naive,naive", "--experiments 'naive,naive' names naive twice"},
      {"--suite 2 --experiments ,", "--experiments ',' has an empty name"},
      {"--suite 2 --experiments ''", "--experiments '' has an empty name"},
      {"--suite 2 --rate -1", "--rate takes a positive number of frames per second, not '-1'"},
      {"--suite 2 --noise x", "--noise takes a sigma in grey levels (>= 0), not 'x'"},
      {"--suite 2 --sim-config /nonexistent.yaml",
       "--sim-config '/nonexistent.yaml' does not exist"},
      {"--suite 2 --receiver nonesuch", "--receiver: no receiver 'nonesuch'"},
      {"--suite 2 --flight-path /tmp/any.csv",
       "--flight-path: a suite flies the approaches it generates"},
      {"--suite=0", "suite: --suite takes a number of approaches of at least 1, not '0'"},
  };
  for (const auto& c : cases) {
    const auto r = Suite(c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
  }
}

std::string Read(const std::string& path) {
  return aar_testing::RunCommand("cat '" + path + "'").output;
}

// A suite campaign created (arguments checked, approaches generated, configuration and provenance
// written, campaign.json saved) as scripts/run --suite creates it, and not flown.
aar_testing::CommandResult CreateSuite(const std::string& args, const std::string& out) {
  const std::string root = aar_testing::WorkspaceRoot();
  return aar_testing::RunCommand(
      "rm -rf " + out + " && cd " + root +
      " && /usr/bin/python3 -c 'import sys; sys.path.insert(0, " +
      "\"scripts\"); from campaign import cli, plans; plans.create(plans.check(\"suite\", " +
      "cli.parser(\"suite\").parse_args(sys.argv[1:])))' " + args + " --out " + out);
}

// --receiver on a suite: its approaches end at that receiver's contact position (other paths than
// the C-12's for the same seed), each run is given it, and the campaign records it; without it the
// suite is the C-12's as before (no receiver named, none copied).
TEST(SuiteScript, AReceiverGivesItsApproachesToTheRunsAndIsRecorded) {
  const std::string c12 = "/tmp/aar_suite_receiver_c12", rq4 = "/tmp/aar_suite_receiver_rq4";
  const std::string args = "--suite 1 --seed 5 --experiments naive,dynamic";
  auto r = CreateSuite(args, c12);
  ASSERT_EQ(r.status, 0) << r.output;
  r = CreateSuite(args + " --receiver rq4", rq4);
  ASSERT_EQ(r.status, 0) << r.output;

  // As the driver names it: the workspace's path without its ".." (os.path.normpath).
  const std::string description =
      std::filesystem::path(aar_testing::WorkspaceRoot() + "/src/aar_description/models/rq4.yaml")
          .lexically_normal()
          .string();
  const std::string runs = Read(rq4 + "/campaign.json");
  size_t named = 0;
  for (size_t at = runs.find("\"receiver\": \"" + description + "\""); at != std::string::npos;
       at = runs.find("\"receiver\": \"" + description + "\"", at + 1))
    ++named;
  EXPECT_EQ(named, 2u) << "each run flies rq4: " << runs;
  EXPECT_NE(Read(c12 + "/campaign.json").find("\"receiver\": \"\""), std::string::npos)
      << Read(c12 + "/campaign.json");

  const std::string path = "/approaches/01/flight_path.csv";
  ASSERT_NE(Read(rq4 + path).find("t,x,y,z"), std::string::npos) << Read(rq4 + path);
  EXPECT_NE(Read(rq4 + path), Read(c12 + path)) << "rq4's approach is the C-12's";

  const std::string provenance = Read(rq4 + "/run.txt");
  EXPECT_NE(provenance.find("command: scripts/run --suite 1 --seed 5 --receiver rq4 --experiments"),
            std::string::npos)
      << provenance;
  EXPECT_NE(provenance.find("receiver: " + description), std::string::npos) << provenance;
  EXPECT_EQ(Read(rq4 + "/config/receiver.yaml"), Read(description));
  const std::string c12_provenance = Read(c12 + "/run.txt");
  EXPECT_EQ(c12_provenance.find("--receiver"), std::string::npos) << c12_provenance;
  EXPECT_EQ(c12_provenance.find("\nreceiver: "), std::string::npos) << c12_provenance;
  EXPECT_NE(aar_testing::RunCommand("test -e " + c12 + "/config/receiver.yaml").status, 0);
  aar_testing::RunCommand("rm -rf " + c12 + " " + rq4);
}

// scripts/run --receiver: an unknown receiver, or one without an approach of its own and no
// --flight-path, is named and refused before setup and build; so are bad --frames and
// --start-time.
TEST(RunScript, BadReceiverIsNamedAndRefused) {
  const std::string run = aar_testing::WorkspaceRoot() + "/scripts/run";
  auto r = aar_testing::RunCommand(run + " --receiver nonesuch --out /tmp/aar_run_script_test");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("run: --receiver: no receiver 'nonesuch'"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("available: c12,rq4"), std::string::npos) << r.output;
  const std::string copy = "/tmp/aar_run_script_test_uav.yaml";  // a description elsewhere
  aar_testing::RunCommand("cp " + aar_testing::ModelsDir() + "/rq4.yaml " + copy);
  r = aar_testing::RunCommand(run + " --receiver " + copy + " --out /tmp/aar_run_script_test");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("has no approach"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("give --flight-path"), std::string::npos) << r.output;
  aar_testing::RunCommand("rm -f " + copy);
  r = aar_testing::RunCommand(run + " --frames x --out /tmp/aar_run_script_test");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("run: --frames takes a whole number (0: all), not 'x'"),
            std::string::npos)
      << r.output;
  r = aar_testing::RunCommand(run + " --start-time 9999 --out /tmp/aar_run_script_test");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--start-time 9999 is outside the flight path's [0, 50.8] s"),
            std::string::npos)
      << r.output;
}

// A --sim-config that sets the simulator's rate counts the run's frames at that rate, as the
// simulator flies them (they were counted at config/sim.yaml's 10 Hz: "30 of 59 frames").
TEST(RunScript, ASimConfigsRateCountsTheFrames) {
  const std::string out = "/tmp/aar_run_script_rate", yaml = "/tmp/aar_run_script_rate5.yaml";
  aar_testing::RunCommand("echo 'rate: 5.0' > " + yaml);
  const auto r = aar_testing::RunCommand(
      "rm -rf " + out + " && cd " + aar_testing::WorkspaceRoot() +
      " && /usr/bin/python3 -c 'import sys; sys.path.insert(0, \"scripts\"); from campaign "
      "import cli, plans; plans.create(plans.check(\"run\", cli.parser(\"run\").parse_args("
      "sys.argv[1:])))' --experiments naive --sim-config " +
      yaml + " --out " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  // The default approach, 0 to 50.8 s: 255 frames at 5 Hz (509 at 10 Hz).
  const std::string runs = Read(out + "/campaign.json");
  EXPECT_NE(runs.find("\"frames\": 255,"), std::string::npos) << runs;
  aar_testing::RunCommand("rm -rf " + out + " " + yaml);
}

// --out at a folder with someone's files in it, or at a file, is refused before anything is
// written there (a campaign writes and deletes files in its folder); the files are kept. So is
// one that cannot be written.
TEST(RunScript, AnOutThatHoldsOtherFilesIsRefusedAndKept) {
  const std::string run = aar_testing::WorkspaceRoot() + "/scripts/run --no-build --frames 5";
  const std::string out = "/tmp/aar_run_script_kept";
  aar_testing::RunCommand("rm -rf " + out + " && mkdir -p " + out + "/naive && echo mine > " + out +
                          "/naive/notes.txt");
  auto r = aar_testing::RunCommand(run + " --out " + out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("'" + out + "' is not empty (naive): a campaign writes and deletes"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(Read(out + "/naive/notes.txt"), "mine\n");
  EXPECT_NE(aar_testing::RunCommand("test -e " + out + "/.lock").status, 0) << "written into";
  r = aar_testing::RunCommand(run + " --out " + out + "/naive/notes.txt");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("is a file, not a folder"), std::string::npos) << r.output;
  EXPECT_EQ(Read(out + "/naive/notes.txt"), "mine\n");
  // A folder that cannot be made or written: named, no traceback.
  r = aar_testing::RunCommand(run + " --out /proc/aar_run_script_test");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--out '/proc/aar_run_script_test' cannot be written: "),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("Traceback"), std::string::npos) << r.output;
  aar_testing::RunCommand("rm -rf " + out);
}

// scripts/run --worlds (a suite per world): worlds that are not presets, a first world other than
// ideal, a --sim-config (each world is its own), and the suite's own bad arguments are named and
// refused (exit 2) before any run.
TEST(WorldsScript, BadArgumentsAreNamedAndRefused) {
  const struct {
    std::string args, needle;
  } cases[] = {
      {"--worlds turbulence", "realism: --worlds must start with ideal"},
      {"--worlds=turbulence", "realism: --worlds must start with ideal"},
      {"--worlds ideal", "--worlds needs ideal and at least one preset"},
      {"--worlds ideal,nope", "no world 'nope': config/realism/nope.yaml does not exist"},
      {"--worlds ideal,all", "no world 'all': config/realism/all.yaml does not exist"},
      {"--suite 0 --worlds ideal,turbulence",
       "--suite takes a number of approaches of at least 1, not '0'"},
      {"--experiments naive,nonsense --worlds ideal,turbulence",
       "no experiment 'nonsense' in config/experiments/"},
      {"--worlds ideal,sun --sim-config config/realism/sun.yaml",
       "--sim-config: with --worlds each world is its own"},
      {"--worlds all --flight-path /tmp/any.csv",
       "--flight-path: a suite flies the approaches it generates"},
      {"--worlds all --bogus", "unrecognized arguments: --bogus"},
      {"--worlds all --out", "argument --out: expected one argument"},
  };
  for (const auto& c : cases) {
    const bool no_out = c.args.size() >= 5 && c.args.compare(c.args.size() - 5, 5, "--out") == 0;
    const auto r =
        aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/run --no-build " + c.args +
                                (no_out ? "" : " --out /tmp/aar_worlds_script_test"));
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
  }
}

// The worlds a campaign of scripts/run --worlds flies: as given, or with `all` ideal and every
// preset of config/realism/, realistic last; each world's folder records the command that
// reproduces the campaign (scripts/run --worlds, which worlds.md prints) and its world.
TEST(WorldsScript, TheWorldsAndTheCommandAreRecorded) {
  const std::string root = aar_testing::WorkspaceRoot();
  const std::string check =
      "cd " + root +
      " && /usr/bin/python3 -c 'import sys; sys.path.insert(0, \"scripts\"); from campaign "
      "import cli, plans; f = plans.check(\"realism\", cli.parser(\"realism\").parse_args("
      "sys.argv[1:])); print(\",\".join(f.worlds), f.suite)' --out /tmp/aar_worlds_script_test ";
  auto r = aar_testing::RunCommand(check + "--worlds all");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output,
            "ideal,all_but_background,background,propellers,sensor,sun,turbulence,realistic 4\n");
  r = aar_testing::RunCommand(check + "--worlds ideal,sun --suite 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output, "ideal,sun 2\n");

  const std::string out = "/tmp/aar_worlds_script_created";
  r = aar_testing::RunCommand(
      "rm -rf " + out + " && cd " + root +
      " && /usr/bin/python3 -c 'import sys; sys.path.insert(0, \"scripts\"); from campaign "
      "import cli, plans; plans.create(plans.check(\"realism\", cli.parser(\"realism\")."
      "parse_args(sys.argv[1:])))' --suite 1 --experiments naive --worlds ideal,sun --out " +
      out);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string command =
      "command: scripts/run --suite 1 --seed 1 --experiments naive "
      "--worlds ideal,sun --rate 10 --noise 2.0 --out " +
      out + "\n";
  for (const std::string world : {"ideal", "sun"}) {
    const std::string provenance = Read(out + "/" + world + "/run.txt");
    EXPECT_NE(provenance.find(command), std::string::npos) << provenance;
    EXPECT_NE(provenance.find("world: " + world + "\n"), std::string::npos) << provenance;
  }
  EXPECT_NE(Read(out + "/campaign.json").find("\"kind\": \"realism\""), std::string::npos);
  aar_testing::RunCommand("rm -rf " + out);
}

}  // namespace

namespace {

// Numeric arguments of the other scripts are checked before anything starts (issue 31: replay's
// --rate 0 or abc grew a shell to 21 GB and never ended, --rate -1 blamed "no truth").
TEST(ScriptArguments, BadNumbersAreNamedAndRefusedAtOnce) {
  const std::string bag = aar_testing::WorkspaceRoot() + "/rosbags/sample_contact.bag";
  const struct {
    std::string command, needle;
  } cases[] = {
      {"replay " + bag + " --rate 0",
       "replay: --rate takes a number above 0 and at most 100, not '0'"},
      {"replay " + bag + " --rate abc",
       "replay: --rate takes a number above 0 and at most 100, not 'abc'"},
      {"replay " + bag + " --rate -1",
       "replay: --rate takes a number above 0 and at most 100, not '-1'"},
      // A number, but far beyond what rosbag and the graph keep up with (was "not a number").
      {"replay " + bag + " --rate 1e9",
       "replay: --rate takes a number above 0 and at most 100, not '1e9'"},
      // A flight path is no live run's frames.csv (was "0 of 29 frames compared").
      {"replay " + bag + " --compare " + aar_testing::DefaultApproachPath(),
       "is not eval's frames.csv of a live run (its columns: t,x,y,z,roll,pitch,yaw; a flight "
       "path?)"},
      {"make-sample-bag --frames 0",
       "make-sample-bag: --frames takes a whole number of at least 1, not '0'"},
      {"make-sample-bag --start x", "make-sample-bag: --start takes a number of at least 0"},
      {"bench-realtime --rate 0", "bench-realtime: --rate takes a number above 0, not '0'"},
      {"bench-realtime --speed -2", "bench-realtime: --speed takes a number above 0, not '-2'"},
  };
  for (const auto& c : cases) {
    const auto r = aar_testing::RunCommand("timeout 60 " + aar_testing::WorkspaceRoot() +
                                           "/scripts/" + c.command + " --no-build");
    EXPECT_EQ(r.status, 2) << c.command << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.command << ": " << r.output;
    EXPECT_LT(r.seconds, 10.0) << c.command;
  }
}

}  // namespace
