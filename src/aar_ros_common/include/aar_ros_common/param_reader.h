#pragma once

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <ros/node_handle.h>

namespace aar_ros_common {

// Reads one node's ~parameters into its options struct: each Get names a key and its default,
// and RejectUnknown refuses any key under ~ that nobody asked for, so a misspelt key stops the
// node instead of being ignored. Every error names the key with the node's namespace.
class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& private_nh) : nh_(private_nh) {}

  // The value, or `fallback` when unset. Throws std::invalid_argument when it has the wrong type.
  template <typename T>
  T Get(const std::string& name, const T& fallback) {
    known_.insert(name);
    T value = fallback;
    if (nh_.hasParam(name) && !nh_.getParam(name, value))
      throw std::invalid_argument("parameter " + nh_.resolveName(name) + " has the wrong type");
    return value;
  }

  // A time, distance or count that must be finite and >= 0 (a NaN or negative timeout would
  // wait forever or not at all). Throws std::invalid_argument naming the key and the value.
  double GetNonNegative(const std::string& name, double fallback) {
    const double value = Get(name, fallback);
    if (!(value >= 0.0 && std::isfinite(value)))
      throw std::invalid_argument("parameter " + nh_.resolveName(name) +
                                  " must be a finite number >= 0, not " + std::to_string(value));
    return value;
  }

  // Throws std::invalid_argument when unset, empty or of the wrong type; `what` says what it is.
  std::string Required(const std::string& name, const std::string& what) {
    const std::string value = Get<std::string>(name, "");
    if (value.empty()) {
      throw std::invalid_argument("required parameter " + nh_.resolveName(name) + " (" + what +
                                  ") is not set");
    }
    return value;
  }

  // One of `choices` by name (`fallback` when unset). Throws std::invalid_argument naming the
  // key and the choices for any other value.
  template <typename Enum>
  Enum GetChoice(const std::string& name, const std::string& fallback,
                 const std::vector<std::pair<std::string, Enum>>& choices) {
    const std::string value = Get<std::string>(name, fallback);
    std::string names;
    for (const auto& [choice, e] : choices) {
      if (choice == value) return e;
      names += (names.empty() ? "" : ", ") + choice;
    }
    throw std::invalid_argument("parameter " + nh_.resolveName(name) + " must be one of " + names +
                                ", not '" + value + "'");
  }

  // A key read by someone else (dynamic_reconfigure, diagnostic_updater, a launch file's habit).
  void Allow(const std::string& name) { known_.insert(name); }
  // Keys below ~ in sub-namespaces (e.g. dynamic_reconfigure's own) are not checked.
  void AllowSubNamespaces() { sub_namespaces_allowed_ = true; }

  // Throws std::invalid_argument naming the first parameter under ~ that Get was never asked for.
  void RejectUnknown() const {
    std::vector<std::string> names;
    nh_.getParamNames(names);
    const std::string prefix = nh_.getNamespace() + "/";
    for (const auto& name : names) {
      if (name.rfind(prefix, 0) != 0) continue;
      const std::string key = name.substr(prefix.size());
      if (sub_namespaces_allowed_ && key.find('/') != std::string::npos) continue;
      if (!known_.count(key))
        throw std::invalid_argument("unknown parameter " + name + " (misspelt?)");
    }
  }

  // Throws std::invalid_argument "parameter ~name <rule>" unless `ok`.
  void Check(bool ok, const std::string& name, const std::string& rule) const {
    if (!ok) throw std::invalid_argument("parameter " + nh_.resolveName(name) + " " + rule);
  }

 private:
  const ros::NodeHandle& nh_;
  std::set<std::string> known_;
  bool sub_namespaces_allowed_ = false;
};

}  // namespace aar_ros_common
