#include "aar_registration/ros/rig_gather.h"

namespace aar_registration {

std::vector<RigGather::Frame> RigGather::Add(size_t rig, const ros::Time& stamp, Cloud cloud,
                                             ros::WallTime now) {
  if (rig >= rigs_) return {};
  auto [it, added] = frames_.try_emplace(stamp);
  Held& held = it->second;
  if (added) {
    held.first = now;
    held.clouds.resize(rigs_);
  }
  if (!held.clouds[rig].points) ++held.count;
  held.clouds[rig] = std::move(cloud);
  if (held.count < rigs_) return {};
  std::vector<Frame> ready;
  while (frames_.begin()->first < stamp) {  // older frames: their late rigs are not waited for
    ready.emplace_back(frames_.begin()->first, std::move(frames_.begin()->second.clouds));
    frames_.erase(frames_.begin());
  }
  ready.push_back(*Take(stamp));
  return ready;
}

std::vector<RigGather::Frame> RigGather::Expire(ros::WallTime now, double wait) {
  std::vector<Frame> expired;
  for (auto it = frames_.begin(); it != frames_.end();) {
    if ((now - it->second.first).toSec() > wait) {
      expired.emplace_back(it->first, std::move(it->second.clouds));
      it = frames_.erase(it);
    } else {
      ++it;
    }
  }
  return expired;
}

std::optional<RigGather::Frame> RigGather::Take(const ros::Time& stamp) {
  auto it = frames_.find(stamp);
  if (it == frames_.end()) return std::nullopt;
  Frame frame{stamp, std::move(it->second.clouds)};
  frames_.erase(it);
  return frame;
}

}  // namespace aar_registration
