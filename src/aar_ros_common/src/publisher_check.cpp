#include "aar_ros_common/publisher_check.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <ros/xmlrpc_manager.h>

namespace aar_ros_common {

namespace {

// This process's own getBusInfo over XML-RPC (roscpp keeps TopicManager's version private): per
// link [id, the other end's XML-RPC URI, "i" (we subscribe) or "o", transport, topic, ...].
bool BusInfo(XmlRpc::XmlRpcValue* links) {
  const std::string& own = ros::XMLRPCManager::instance()->getServerURI();
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(own, host, port)) return false;
  XmlRpc::XmlRpcClient* client =
      ros::XMLRPCManager::instance()->getXMLRPCClient(host, static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = ros::this_node::getName();
  const bool ok =
      client->execute("getBusInfo", args, result) &&
      ros::XMLRPCManager::instance()->validateXmlrpcResponse("getBusInfo", result, *links);
  ros::XMLRPCManager::instance()->releaseXMLRPCClient(client);
  return ok;
}

}  // namespace

std::vector<std::string> LinkedPublishers(const std::string& topic) {
  XmlRpc::XmlRpcValue info;
  std::vector<std::string> uris;
  if (!BusInfo(&info) || info.getType() != XmlRpc::XmlRpcValue::TypeArray) return uris;
  for (int i = 0; i < info.size(); ++i) {
    XmlRpc::XmlRpcValue& link = info[i];
    if (link.getType() != XmlRpc::XmlRpcValue::TypeArray || link.size() < 5) continue;
    if (link[1].getType() != XmlRpc::XmlRpcValue::TypeString ||
        link[2].getType() != XmlRpc::XmlRpcValue::TypeString ||
        link[4].getType() != XmlRpc::XmlRpcValue::TypeString) {
      continue;
    }
    if (std::string(link[2]) == "i" && std::string(link[4]) == topic) uris.push_back(link[1]);
  }
  return uris;
}

PublisherCheck::PublisherCheck(std::string topic, std::string node)
    : topic_(std::move(topic)), node_(std::move(node)) {}

bool PublisherCheck::LookUp() {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node_;
  if (!ros::master::execute("lookupNode", args, result, payload, false) ||
      payload.getType() != XmlRpc::XmlRpcValue::TypeString) {
    return false;
  }
  node_uri_ = std::string(payload);
  return true;
}

std::vector<std::string> PublisherCheck::Strangers() {
  const std::vector<std::string> linked = LinkedPublishers(topic_);
  const auto unknown = [&](const std::string& uri) { return uri != node_uri_; };
  // Asked again only when a link does not match: the node may have moved (a respawn). A master
  // that cannot answer (restarting) leaves the URI it gave last.
  if (std::any_of(linked.begin(), linked.end(), unknown)) LookUp();
  std::vector<std::string> strangers;
  std::copy_if(linked.begin(), linked.end(), std::back_inserter(strangers), unknown);
  return strangers;
}

std::vector<std::string> PublisherCheck::StrangersIfChanged(uint32_t links, double recheck) {
  const auto now = std::chrono::steady_clock::now();
  if (links != 0 && links == clean_links_ && now < clean_until_) return {};
  std::vector<std::string> strangers = Strangers();
  clean_links_ = strangers.empty() ? links : 0;
  clean_until_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(recheck));
  return strangers;
}

std::string PublisherCheck::Describe(const std::vector<std::string>& strangers) const {
  std::string named;
  for (const std::string& s : strangers) named += (named.empty() ? "" : ", ") + s;
  return named + " (the master lists " + node_ + " at " +
         (node_uri_.empty() ? std::string("no address") : node_uri_) + ")";
}

}  // namespace aar_ros_common
