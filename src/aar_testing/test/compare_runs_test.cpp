// scripts/compare-runs, the check that a change keeps every experiment's per-frame results: the
// same cells are identical, timings are not compared, a column only one run has is named, and
// any other difference fails, a NaN against a number too (it once passed: NaN compares false).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace {

const char kDir[] = "/tmp/aar_compare_runs";

void WriteRun(const std::string& run, const std::string& csv) {
  aar_testing::RunCommand("mkdir -p " + std::string(kDir) + "/" + run + "/flight");
  std::ofstream(std::string(kDir) + "/" + run + "/flight/frames.csv") << csv;
}

aar_testing::CommandResult Compare(const std::string& a, const std::string& b) {
  return aar_testing::RunCommand(aar_testing::WorkspaceRoot() + "/scripts/compare-runs " + kDir +
                                 "/" + a + " " + kDir + "/" + b);
}

TEST(CompareRuns, SameCellsPassAndANanAgainstANumberFails) {
  aar_testing::RunCommand(std::string("rm -rf ") + kDir);
  WriteRun("a", "t,x_m,registration_ms,pl_position_m\n0,0.5,10,nan\n0.1,0.25,11,0.75\n");
  WriteRun("b", "t,x_m,registration_ms,pl_position_m\n0,0.5,99,nan\n0.1,0.25,98,0.75\n");
  WriteRun("c", "t,x_m,registration_ms,pl_position_m\n0,0.5,10,0.5\n0.1,0.25,11,0.75\n");
  WriteRun("d",
           "t,x_m,registration_ms,pl_position_m,visible_px\n0,0.5,10,nan,7\n0.1,0.25,11,0.75,8\n");
  const auto same = Compare("a", "b");
  EXPECT_EQ(same.status, 0) << same.output;
  EXPECT_NE(same.output.find("flight: 2 frames identical (3 columns; timings not compared)"),
            std::string::npos)
      << same.output;
  const auto nan = Compare("a", "c");
  EXPECT_EQ(nan.status, 1) << nan.output;
  EXPECT_NE(nan.output.find("flight: 2 frames DIFFER: largest pl_position_m by inf (t 0)"),
            std::string::npos)
      << nan.output;
  const auto newer = Compare("a", "d");
  EXPECT_EQ(newer.status, 0) << newer.output;
  EXPECT_NE(newer.output.find("columns in one run only, not compared: visible_px"),
            std::string::npos)
      << newer.output;
}

}  // namespace
