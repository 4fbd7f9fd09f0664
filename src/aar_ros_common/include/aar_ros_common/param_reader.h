#pragma once

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace aar_ros_common {

// Reads one node's ~parameters into its options struct: each Get names a key and its default,
// and RejectUnknown refuses any key under ~ that nobody asked for, so a misspelt key stops the
// node instead of being ignored. Every error names the key with the node's namespace.
//
// Values are read as XmlRpcValues and converted here, with roscpp's rules but two: an int key
// takes a double only when it is a whole number in int's range (roscpp rounds any double and
// converts 1e10 with undefined behaviour), and a double must be finite (YAML's .nan, .inf).
class ParamReader {
 public:
  // The parameter server, below private_nh's namespace.
  explicit ParamReader(const ros::NodeHandle& private_nh) : nh_(&private_nh) {}
  // A parameter tree as the server holds it (`tree` is "/", each struct a namespace, as
  // `rosparam load` stores a YAML file), read as the node whose private namespace is `ns`
  // (e.g. "/stereo/aar_stereo"). Needs no master: the parameter fuzz target reads through it.
  ParamReader(XmlRpc::XmlRpcValue tree, const std::string& ns);

  // The value, or `fallback` when unset. Throws std::invalid_argument when it has the wrong type
  // (T is bool, int, double or std::string).
  template <typename T>
  T Get(const std::string& name, const T& fallback) {
    known_.insert(name);
    XmlRpc::XmlRpcValue value;
    if (!GetValue(name, value)) return fallback;
    T out = fallback;
    Convert(name, value, out);
    return out;
  }

  // The raw value of a key (true), or false when unset. Does not count as reading it.
  bool GetValue(const std::string& name, XmlRpc::XmlRpcValue& value) const;

  // A time, distance or count that must be finite and >= 0 (a NaN or negative timeout would
  // wait forever or not at all). Throws std::invalid_argument naming the key and the value.
  double GetNonNegative(const std::string& name, double fallback) {
    const double value = Get(name, fallback);
    if (!(value >= 0.0 && std::isfinite(value)))
      throw std::invalid_argument("parameter " + Resolve(name) +
                                  " must be a finite number >= 0, not " + std::to_string(value));
    return value;
  }

  // A sigma, rate or duration that must be finite and > 0. Throws std::invalid_argument naming
  // the key and the value.
  double GetPositive(const std::string& name, double fallback) {
    const double value = Get(name, fallback);
    if (!(value > 0.0 && std::isfinite(value)))
      throw std::invalid_argument("parameter " + Resolve(name) +
                                  " must be a finite number > 0, not " + std::to_string(value));
    return value;
  }

  // Throws std::invalid_argument when unset, empty or of the wrong type; `what` says what it is.
  std::string Required(const std::string& name, const std::string& what) {
    const std::string value = Get<std::string>(name, "");
    if (value.empty()) {
      throw std::invalid_argument("required parameter " + Resolve(name) + " (" + what +
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
    throw std::invalid_argument("parameter " + Resolve(name) + " must be one of " + names +
                                ", not '" + value + "'");
  }

  // A key read by someone else (dynamic_reconfigure, diagnostic_updater, a launch file's habit).
  void Allow(const std::string& name) { known_.insert(name); }
  // Every key read or allowed so far (config.test checks a node YAML lists all of its loader's).
  const std::set<std::string>& known_keys() const { return known_; }
  // Keys below ~ in sub-namespaces (e.g. dynamic_reconfigure's own) are not checked.
  void AllowSubNamespaces() { sub_namespaces_allowed_ = true; }

  // Throws std::invalid_argument naming the first parameter under ~ that Get was never asked for.
  void RejectUnknown() const;

  // Throws std::invalid_argument "parameter ~name <rule>" unless `ok`.
  void Check(bool ok, const std::string& name, const std::string& rule) const {
    if (!ok) throw std::invalid_argument("parameter " + Resolve(name) + " " + rule);
  }

  // The key's full name, as errors give it.
  std::string Resolve(const std::string& name) const;

 private:
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value, bool& out) const;
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value, int& out) const;
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value, double& out) const;
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value, std::string& out) const;
  // A list of numbers, each finite.
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value,
               std::vector<double>& out) const;
  // A list of strings.
  void Convert(const std::string& name, const XmlRpc::XmlRpcValue& value,
               std::vector<std::string>& out) const;

  const ros::NodeHandle* nh_ = nullptr;  // the server; else tree_ and ns_
  XmlRpc::XmlRpcValue tree_;
  std::string ns_;
  std::set<std::string> known_;
  bool sub_namespaces_allowed_ = false;
};

}  // namespace aar_ros_common
