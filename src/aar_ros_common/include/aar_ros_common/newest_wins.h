#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace aar_ros_common {

// The subscriber queue of a stage whose callback only hands its input to a NewestWins: a second
// of frames at 30 Hz. The callback returns at once, so the queue fills only while the process is
// not scheduled at all (a stall); it takes those frames in so that the stage, not the subscriber
// queue, skips them, and counts them.
constexpr uint32_t kHandOverQueue = 30;

// A stage that never queues (issue 28): at most one item waits while the worker processes
// another, and a new item replaces a waiting one, which is counted as superseded. Put returns at
// once, so a subscriber callback never blocks behind processing and ROS never drops a message
// unseen from a full subscriber queue. The work runs on a thread of its own, one item at a time,
// in the order Put was called (minus the superseded items).
template <typename T>
class NewestWins {
 public:
  explicit NewestWins(std::function<void(T&)> work)
      : work_(std::move(work)), thread_([this] { Run(); }) {}
  ~NewestWins() { Stop(); }
  NewestWins(const NewestWins&) = delete;
  NewestWins& operator=(const NewestWins&) = delete;

  // Hands `item` to the worker. Returns true if it replaced a waiting item (superseded).
  bool Put(T item) { return Put(std::move(item), nullptr); }
  // The same; the item it replaced, if any, is moved to `*replaced` (for the frame ledger).
  bool Put(T item, std::optional<T>* replaced) {
    bool was_waiting = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return false;
      was_waiting = waiting_.has_value();
      superseded_ += was_waiting;
      if (was_waiting && replaced) *replaced = std::move(waiting_);
      waiting_ = std::move(item);
    }
    wake_.notify_one();
    return was_waiting;
  }

  // Ends the worker after the item it is processing; a waiting item is dropped. Idempotent.
  void Stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  uint64_t superseded() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return superseded_;
  }
  uint64_t processed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return processed_;
  }

 private:
  void Run() {
    for (;;) {
      std::optional<T> item;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || waiting_.has_value(); });
        if (stop_) return;
        item = std::move(waiting_);
        waiting_.reset();
      }
      work_(*item);
      std::lock_guard<std::mutex> lock(mutex_);
      ++processed_;
    }
  }

  std::function<void(T&)> work_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<T> waiting_;
  bool stop_ = false;
  uint64_t superseded_ = 0, processed_ = 0;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace aar_ros_common
