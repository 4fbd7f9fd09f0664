// The frame ledger under load (docs/RELIABILITY.md, Load): scripts/replay plays the sample bag at
// its recorded speed while stress-ng keeps both cores busy and holds memory. Frames may be
// dropped (the graph falls behind), but every frame sent has one outcome in eval's ledger.csv,
// each drop names its stage and reason, and nothing crashes.
#include <gtest/gtest.h>

#include <signal.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"
#include "aar_testing/time_scale.h"

namespace {

const std::string kRoot = aar_testing::WorkspaceRoot();

// stress-ng from Debian, in a process group of its own, bounded by its own --timeout and
// stopped when the test is done.
class Hog {
 public:
  explicit Hog(const std::string& args) {
    const aar_testing::CommandResult r =
        aar_testing::RunCommand("setsid stress-ng " + args + " --quiet >/dev/null 2>&1 & echo $!");
    pid_ = std::atoi(r.output.c_str());
  }
  ~Hog() {
    if (pid_ > 0) kill(-pid_, SIGKILL);
  }
  int pid() const { return pid_; }

 private:
  int pid_ = 0;
};

// outcome -> count, and "stage reason" -> count of the dropped rows, from ledger.csv.
struct Ledger {
  int rows = 0;
  std::map<std::string, int> outcomes, drops;
};

Ledger ReadLedger(const std::string& path) {
  Ledger l;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string t, stamp, outcome, stage, reason;
    std::getline(s, t, ',');
    std::getline(s, stamp, ',');
    std::getline(s, outcome, ',');
    std::getline(s, stage, ',');
    std::getline(s, reason, ',');
    ++l.rows;
    ++l.outcomes[outcome];
    if (outcome == "dropped") ++l.drops[stage + " " + reason];
  }
  return l;
}

TEST(Load, ReplayUnderACpuHogAndMemoryPressureAccountsForEveryFrame) {
  ASSERT_EQ(aar_testing::RunCommand("command -v stress-ng").status, 0)
      << "stress-ng is missing: scripts/setup installs it (scripts/debian-packages.txt)";
  const std::string out = ::testing::TempDir() + "/replay_load";
  std::filesystem::remove_all(out);
  // Two CPU hogs (one per core) and 4 GB kept resident, for at most 150 s.
  Hog hog("--cpu 2 --vm 1 --vm-bytes 4G --vm-keep --timeout 150s");
  ASSERT_GT(hog.pid(), 0);
  const aar_testing::CommandResult r = aar_testing::RunCommand(
      "timeout 200 " + kRoot +
      "/scripts/replay --no-build --no-compare --experiment dynamic --rate 1 " + kRoot +
      "/rosbags/sample_contact.bag --out " + out + " 2>&1");
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(aar_testing::RunCommand("kill -0 " + std::to_string(hog.pid())).status, 0)
      << "the hog ended before the replay did: the load did not last";
  // 0: every frame estimated; 3: some without an estimate, counted. Not 1: frames lost unseen.
  EXPECT_TRUE(r.status == 0 || r.status == 3) << "status " << r.status;
  const Ledger l = ReadLedger(out + "/dynamic/ledger.csv");
  EXPECT_EQ(l.rows, 30) << "every frame sent has one outcome";
  const std::set<std::string> known = {"estimated", "coasted", "lost", "no_pose", "dropped"};
  for (const auto& [outcome, n] : l.outcomes) {
    EXPECT_TRUE(known.count(outcome)) << "unknown outcome " << outcome;
    std::printf("[ load ] %s: %d\n", outcome.c_str(), n);
  }
  for (const auto& [where, n] : l.drops) {
    EXPECT_NE(where.find(' '), std::string::npos);
    EXPECT_GT(where.size(), 3u) << "a drop without stage or reason";
    std::printf("[ load ] dropped by %s: %d\n", where.c_str(), n);
  }
  EXPECT_NE(r.output.find("replay: 30 frames:"), std::string::npos) << "no ledger line";
  EXPECT_NE(r.output.find("0 of 30 frames sent never reached eval"), std::string::npos);
  std::ifstream log(out + "/dynamic/launch.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("process has died"), std::string::npos) << "a process crashed";
}

}  // namespace
