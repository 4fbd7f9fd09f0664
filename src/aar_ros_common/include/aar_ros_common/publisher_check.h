#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace aar_ros_common {

// Who publishes on a topic this node subscribes to, read from the connections themselves: the
// XML-RPC URI of each publisher this node's subscription is linked to (the address and port it
// was given by the master and connected to), not the caller id a sender writes into its own
// connection header, which any node can forge. Only `node` may publish: the URI the master lists
// for it is looked up when needed (again when a link does not match it: a respawned node has a
// new port). ROS 1 proves no more than this: a node that registers under `node`'s own name takes
// its place at the master, and the master shuts the old one down (see docs/MULTI_HOST.md).
class PublisherCheck {
 public:
  // `topic`: resolved (e.g. "/aar/pose_estimate"); `node`: e.g. "/aar_manager".
  PublisherCheck(std::string topic, std::string node);

  // The publishers linked to `topic` that are not `node`, each as "URI" (empty: none). While the
  // master cannot be asked (restarting), `node` is where it was last.
  std::vector<std::string> Strangers();

  // Strangers(), read again only when the subscription's link count (`links`, from
  // ros::Subscriber::getNumPublishers, which costs nothing) differs from the last count found
  // clean, or `recheck` [s wall] after that read: a link added is seen on its first message, a
  // link swapped for another at the same count within `recheck`. Reading the links is an
  // XML-RPC call to this node; per message it slowed a loaded machine's eval.
  std::vector<std::string> StrangersIfChanged(uint32_t links, double recheck = 1.0);

  // `strangers` (URIs or other names of what is linked) as the messages name them:
  // "URI, URI (the master lists /node at URI)", or "... at no address" before a look-up.
  std::string Describe(const std::vector<std::string>& strangers) const;

  const std::string& node() const { return node_; }

 private:
  bool
  LookUp();  // the master's URI for node_ into node_uri_; false (unchanged) if it could not say

  std::string topic_, node_, node_uri_;
  uint32_t clean_links_ = 0;  // the link count last found clean (0: none yet)
  std::chrono::steady_clock::time_point clean_until_;
};

// The XML-RPC URIs of the publishers this process's subscriptions to `topic` are linked to (one
// per link; intra-process links give this process's own URI).
std::vector<std::string> LinkedPublishers(const std::string& topic);

}  // namespace aar_ros_common
