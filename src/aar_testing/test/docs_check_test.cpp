// scripts/lib/check_docs.py (scripts/lint, issue 45 item 7): a doc naming a script, an option of
// scripts/run, an experiment or a file that does not exist is named with its file and line, and
// the check fails (status 1); a doc naming only what exists, placeholders and a refused example
// passes (status 0); a doc that cannot be read is bad input (status 2).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

const char kDir[] = "/tmp/aar_docs_check";

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = std::string(kDir) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

aar_testing::CommandResult Check(const std::string& files) {
  return aar_testing::RunCommand("python3 " + aar_testing::WorkspaceRoot() +
                                 "/scripts/lib/check_docs.py " + files);
}

TEST(DocsCheck, WhatDoesNotExistIsNamedWithItsLine) {
  aar_testing::RunCommand(std::string("rm -rf ") + kDir + " && mkdir -p " + kDir);
  const std::string bad = Write("bad.md",
                                "# Stale\n"
                                "\n"
                                "`scripts/run --suite 4 --experiments dynamic,no_such_experiment`\n"
                                "then `scripts/nonexistent` and\n"
                                "```\n"
                                "scripts/run --frames 40 --no-such-flag\n"
                                "roslaunch launch/pipeline.launch experiment:=ghost\n"
                                "```\n"
                                "See docs/NO_SUCH.md and [this](missing.md).\n"
                                "\n"
                                "| experiment | what |\n"
                                "|---|---|\n"
                                "| `phantom` | gone |\n");
  const auto r = Check(bad);
  EXPECT_EQ(r.status, 1) << r.output;
  for (const char* finding :
       {"bad.md:3: no experiment no_such_experiment (config/experiments/no_such_experiment.yaml)",
        "bad.md:4: no script scripts/nonexistent",
        "bad.md:6: scripts/run has no option --no-such-flag", "bad.md:7: no experiment ghost",
        "bad.md:9: no file docs/NO_SUCH.md", "bad.md:9: no file missing.md (linked)",
        "bad.md:13: no experiment phantom"})
    EXPECT_NE(r.output.find(finding), std::string::npos) << finding << " not in\n" << r.output;
  for (const char* existing : {"dynamic ", "--suite", "--frames", "launch/pipeline.launch"})
    EXPECT_EQ(r.output.find(existing), std::string::npos) << existing << " named:\n" << r.output;
}

TEST(DocsCheck, ADocNamingWhatExistsPasses) {
  aar_testing::RunCommand(std::string("rm -rf ") + kDir + " && mkdir -p " + kDir);
  const std::string good = Write(
      "good.md",
      "`scripts/run --suite 4 --seed 1 --jobs 2 --experiments naive,flight --out DIR`\n"
      "(docs/USAGE.md, config/experiments/flight.yaml, aar_sim/sensor.h; placeholders:\n"
      "`scripts/run --show-experiment NAME`, `--experiments a,b,...`, `--experiments <copy>`,\n"
      "config/mounts/NAME.yaml). A refused example, its refusal on the same line:\n"
      "| `--experiments naive,nonsense` | \"no experiment 'nonsense' in config/experiments/\" |\n");
  const auto r = Check(good);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("1 files, every name exists"), std::string::npos) << r.output;
  const auto unreadable = Check(std::string(kDir) + "/nonexistent.md");
  EXPECT_EQ(unreadable.status, 2) << unreadable.output;
  EXPECT_NE(unreadable.output.find("nonexistent.md: not a readable file"), std::string::npos)
      << unreadable.output;
}

}  // namespace
