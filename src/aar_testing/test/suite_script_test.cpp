// scripts/run --suite refuses bad arguments with a message naming them and a non-zero exit,
// before anything is set up, built or flown (the campaign driver, scripts/campaign/, checks them).
#include <gtest/gtest.h>

#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

aar_testing::CommandResult Suite(const std::string& args) {
  return aar_testing::RunCommand("/usr/bin/python3 " + aar_testing::WorkspaceRoot() +
                                 "/scripts/suite " + args + " --out /tmp/aar_suite_script_test");
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
      {"--suite 2 --rate -1", "--rate takes a positive number of frames per second, not '-1'"},
      {"--suite 2 --noise x", "--noise takes a sigma in grey levels (>= 0), not 'x'"},
      {"--suite 2 --sim-config /nonexistent.yaml",
       "--sim-config '/nonexistent.yaml' does not exist"},
  };
  for (const auto& c : cases) {
    const auto r = Suite(c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
  }
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

// scripts/realism: worlds that are not presets, a first world other than ideal, and the suite's
// own bad arguments are named and refused (exit 2) before any run.
TEST(RealismScript, BadArgumentsAreNamedAndRefused) {
  const struct {
    std::string args, needle;
  } cases[] = {
      {"--worlds turbulence", "--worlds must start with ideal"},
      {"--worlds ideal", "--worlds needs ideal and at least one preset"},
      {"--worlds ideal,nope", "no world 'nope': config/realism/nope.yaml does not exist"},
      {"--suite 0 --worlds ideal,turbulence",
       "--suite takes a number of approaches of at least 1, not '0'"},
      {"--experiments naive,nonsense --worlds ideal,turbulence",
       "no experiment 'nonsense' in config/experiments/"},
      {"--bogus", "unrecognized arguments: --bogus"},
      {"--out", "argument --out: expected one argument"},
  };
  for (const auto& c : cases) {
    const auto r =
        aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/realism --no-build " +
                                c.args + (c.args == "--out" ? "" : " --out /tmp/aar_realism_test"));
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << ": " << r.output;
  }
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
      {"replay " + bag + " --rate 0", "replay: --rate takes a number above 0, not '0'"},
      {"replay " + bag + " --rate abc", "replay: --rate takes a number above 0, not 'abc'"},
      {"replay " + bag + " --rate -1", "replay: --rate takes a number above 0, not '-1'"},
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
