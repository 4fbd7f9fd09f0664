#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <ros/ros.h>

#include "aar_ros_common/frame_ledger.h"
#include "aar_ros_common/newest_wins.h"

namespace aar_ros_common {

// How a stage's subscriber callbacks hand a frame to its work, written once for every stage:
// inline when `newest_wins` is off (the callback's thread does the work), else through a
// NewestWins (a worker thread; a frame that still waited when a newer one came is dropped in the
// frame ledger as "superseded" and warned about at most every 5 s, with the count). The ledger
// is the one count of superseded frames (its /diagnostics key "ledger: frames dropped:
// superseded").
template <typename T>
class Stage {
 public:
  struct Names {
    std::string stage;  // "stereo": the messages' prefix
    std::string item;   // "pair", "cloud"
    std::string work;   // "matching", "culling", "registration"
  };

  // `stamp`: the frame's stamp, for the ledger. `ledger` must outlive the stage.
  Stage(bool newest_wins, std::function<void(T&)> work, std::function<ros::Time(const T&)> stamp,
        FrameLedger& ledger, Names names)
      : work_(work), stamp_(std::move(stamp)), ledger_(ledger), names_(std::move(names)) {
    if (newest_wins) worker_ = std::make_unique<NewestWins<T>>(std::move(work));
  }

  // The subscriber queue this hand-over needs: `inline_queue`, and with a worker at least
  // kHandOverQueue (the callback only hands over; the queue takes in a stall).
  uint32_t queue(uint32_t inline_queue) const {
    return worker_ ? std::max(inline_queue, kHandOverQueue) : inline_queue;
  }

  void Hand(T item) {
    if (!worker_) {
      work_(item);
      return;
    }
    std::optional<T> replaced;
    if (!worker_->Put(std::move(item), &replaced) || !replaced) return;
    const uint64_t superseded =
        ledger_.Dropped(stamp_(*replaced), "superseded",
                        "a newer " + names_.item + " came while it waited for " + names_.work);
    ROS_WARN_STREAM_THROTTLE(5.0, names_.stage << ": a " << names_.item
                                               << " arrived while the previous one still waited "
                                                  "for "
                                               << names_.work
                                               << ": the older one skipped, the newest wins ("
                                               << superseded << " superseded so far)");
  }

  // Ends the worker after the frame it is processing (a waiting one is dropped); idempotent.
  void Stop() {
    if (worker_) worker_->Stop();
  }

 private:
  std::function<void(T&)> work_;
  std::function<ros::Time(const T&)> stamp_;
  FrameLedger& ledger_;
  Names names_;
  std::unique_ptr<NewestWins<T>> worker_;
};

}  // namespace aar_ros_common
