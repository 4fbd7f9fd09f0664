#include "aar_ros_common/newest_wins.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <vector>

namespace aar_ros_common {
namespace {

// A worker slower than its input skips to the newest item and counts every skipped one; nothing
// is processed twice or out of order, and Put never waits for the work.
TEST(NewestWins, SlowWorkerSkipsToTheNewestAndCountsTheSkips) {
  std::mutex seen_mutex;
  std::vector<int> seen;
  std::atomic<bool> started{false}, release{false};
  NewestWins<int> stage([&](int& item) {
    started = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::lock_guard<std::mutex> lock(seen_mutex);
    seen.push_back(item);
  });
  EXPECT_FALSE(stage.Put(0));
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  // The worker is busy with 0: 1..50 arrive, each replacing the one waiting.
  const auto t0 = std::chrono::steady_clock::now();
  int replaced = 0;
  for (int i = 1; i <= 50; ++i) replaced += stage.Put(i);
  const double put_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  release = true;
  while (stage.processed() < 2 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  stage.Stop();
  std::lock_guard<std::mutex> lock(seen_mutex);
  EXPECT_EQ(seen, (std::vector<int>{0, 50}));  // the one in flight, then the newest
  EXPECT_EQ(replaced, 49);
  EXPECT_EQ(stage.superseded(), 49u);  // every skipped item counted
  EXPECT_EQ(stage.processed(), 2u);
  EXPECT_LT(put_ms, 1000.0);  // no Put waited for the blocked worker
}

// The frame ledger needs to know which item was skipped: Put hands back the one it replaced.
TEST(NewestWins, PutHandsBackTheItemItReplaced) {
  std::atomic<bool> started{false}, release{false};
  NewestWins<int> stage([&](int&) {
    started = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  std::optional<int> replaced;
  EXPECT_FALSE(stage.Put(1, &replaced));
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_FALSE(stage.Put(2, &replaced));  // waits: nothing replaced
  EXPECT_FALSE(replaced.has_value());
  EXPECT_TRUE(stage.Put(3, &replaced));
  EXPECT_EQ(replaced, 2);
  EXPECT_TRUE(stage.Put(4, &replaced));
  EXPECT_EQ(replaced, 3);
  release = true;
  stage.Stop();
}

TEST(NewestWins, StopDropsTheWaitingItemAndRefusesNewOnes) {
  std::atomic<int> done{0};
  NewestWins<int> stage([&](int&) { ++done; });
  stage.Put(1);
  stage.Stop();
  stage.Stop();  // idempotent
  EXPECT_FALSE(stage.Put(2));
  EXPECT_LE(done.load(), 1);
}

}  // namespace
}  // namespace aar_ros_common
