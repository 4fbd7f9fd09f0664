#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include <ros/time.h>
#include <sensor_msgs/PointCloud2.h>

namespace aar_registration {

// A frame's clouds from more than one stereo rig, gathered by their common stamp (issue 44: the
// rigs are triggered together, so a frame's clouds share its stamp). A frame is handed on when
// every rig's cloud has come, or when it has waited too long (the rigs that came). Not
// thread-safe: the node guards it.
class RigGather {
 public:
  // One rig's sensed cloud and, with a reference topic, the reference built for its stamp.
  struct Cloud {
    sensor_msgs::PointCloud2::ConstPtr points, reference;
  };
  using Frame = std::pair<ros::Time, std::vector<Cloud>>;  // clouds in rig order, null: missing

  explicit RigGather(size_t rigs) : rigs_(rigs) {}

  // Rig `rig`'s cloud of `stamp`, first seen at `now`. When that completes its frame: the older
  // frames still held, as they are (their missing rigs' clouds would come out of order), then
  // this one, in stamp order, none held any longer; else nothing. A second cloud of one rig and
  // stamp replaces the first.
  std::vector<Frame> Add(size_t rig, const ros::Time& stamp, Cloud cloud, ros::WallTime now);
  // The frames whose first cloud came more than `wait` [s] before `now`, oldest stamp first (no
  // longer held).
  std::vector<Frame> Expire(ros::WallTime now, double wait);
  // A frame of `stamp` is held (some rig's cloud came, not every one).
  bool Holds(const ros::Time& stamp) const { return frames_.count(stamp) > 0; }
  // Takes the frame of `stamp` as it is (nullopt when none is held).
  std::optional<Frame> Take(const ros::Time& stamp);
  size_t held() const { return frames_.size(); }

 private:
  struct Held {
    ros::WallTime first;
    std::vector<Cloud> clouds;
    size_t count = 0;
  };
  size_t rigs_;
  std::map<ros::Time, Held> frames_;
};

}  // namespace aar_registration
