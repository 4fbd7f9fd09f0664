#include "aar_ros_common/param_reader.h"

#include <climits>
#include <cmath>
#include <sstream>

namespace aar_ros_common {
namespace {

using XmlRpc::XmlRpcValue;

const char* TypeName(XmlRpcValue::Type type) {
  switch (type) {
    case XmlRpcValue::TypeBoolean:
      return "a bool";
    case XmlRpcValue::TypeInt:
      return "an int";
    case XmlRpcValue::TypeDouble:
      return "a double";
    case XmlRpcValue::TypeString:
      return "a string";
    case XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpcValue::TypeStruct:
      return "a map";
    default:
      return "another type";
  }
}

// Every leaf below `value` as the master's getParamNames lists it (maps are namespaces).
void LeafNames(const XmlRpcValue& value, const std::string& name, std::vector<std::string>& out) {
  if (value.getType() != XmlRpcValue::TypeStruct) {
    out.push_back(name);
    return;
  }
  for (const auto& [key, child] : value) LeafNames(child, name + "/" + key, out);
}

}  // namespace

ParamReader::ParamReader(XmlRpc::XmlRpcValue tree, const std::string& ns)
    : tree_(std::move(tree)), ns_(ns) {
  while (!ns_.empty() && ns_.back() == '/') ns_.pop_back();  // "/" is the root: ""
  if (!ns_.empty() && ns_.front() != '/') ns_ = "/" + ns_;
}

std::string ParamReader::Resolve(const std::string& name) const {
  if (nh_ != nullptr) return nh_->resolveName(name);
  return !name.empty() && name.front() == '/' ? name : ns_ + "/" + name;
}

bool ParamReader::GetValue(const std::string& name, XmlRpc::XmlRpcValue& value) const {
  if (nh_ != nullptr) return nh_->getParam(name, value);
  const XmlRpcValue* node = &tree_;
  std::stringstream path(Resolve(name));
  for (std::string key; std::getline(path, key, '/');) {
    if (key.empty()) continue;
    if (node->getType() != XmlRpcValue::TypeStruct || !node->hasMember(key)) return false;
    node = &(*node)[key];
  }
  if (!node->valid()) return false;
  value = *node;
  return true;
}

void ParamReader::RejectUnknown() const {
  std::vector<std::string> names;
  std::string prefix;
  if (nh_ != nullptr) {
    nh_->getParamNames(names);
    prefix = nh_->getNamespace() + "/";
  } else {
    if (tree_.getType() == XmlRpcValue::TypeStruct) {
      for (const auto& [key, child] : tree_) LeafNames(child, "/" + key, names);
    }
    prefix = ns_ + "/";
  }
  for (const auto& name : names) {
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string key = name.substr(prefix.size());
    if (sub_namespaces_allowed_ && key.find('/') != std::string::npos) continue;
    if (!known_.count(key))
      throw std::invalid_argument("unknown parameter " + name + " (misspelt?)");
  }
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value, bool& out) const {
  Check(value.getType() == XmlRpcValue::TypeBoolean, name,
        std::string("has the wrong type (a bool expected, not ") + TypeName(value.getType()) + ")");
  out = static_cast<const bool&>(value);
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value, int& out) const {
  if (value.getType() == XmlRpcValue::TypeInt) {
    out = static_cast<const int&>(value);
    return;
  }
  Check(value.getType() == XmlRpcValue::TypeDouble, name,
        std::string("has the wrong type (an int expected, not ") + TypeName(value.getType()) + ")");
  const double d = static_cast<const double&>(value);
  std::ostringstream rule;
  rule << "must be a whole number from " << INT_MIN << " to " << INT_MAX << ", not " << d;
  Check(std::floor(d) == d && d >= INT_MIN && d <= INT_MAX, name, rule.str());
  out = static_cast<int>(d);
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value, double& out) const {
  if (value.getType() == XmlRpcValue::TypeInt) {
    out = static_cast<const int&>(value);
    return;
  }
  Check(
      value.getType() == XmlRpcValue::TypeDouble, name,
      std::string("has the wrong type (a number expected, not ") + TypeName(value.getType()) + ")");
  const double d = static_cast<const double&>(value);
  // YAML's .nan and .inf: no setting means either (the params fuzz target found the simulator
  // taking camera_x .nan and stamp_offset .inf).
  std::ostringstream rule;
  rule << "must be a finite number, not " << d;
  Check(std::isfinite(d), name, rule.str());
  out = d;
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value,
                          std::string& out) const {
  Check(
      value.getType() == XmlRpcValue::TypeString, name,
      std::string("has the wrong type (a string expected, not ") + TypeName(value.getType()) + ")");
  out = static_cast<const std::string&>(value);
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value,
                          std::vector<double>& out) const {
  Check(value.getType() == XmlRpcValue::TypeArray, name,
        std::string("has the wrong type (a list of numbers expected, not ") +
            TypeName(value.getType()) + ")");
  out.clear();
  for (int i = 0; i < value.size(); ++i) {
    double d = 0.0;
    Convert(name + "[" + std::to_string(i) + "]", value[i], d);
    out.push_back(d);
  }
}

void ParamReader::Convert(const std::string& name, const XmlRpcValue& value,
                          std::vector<std::string>& out) const {
  Check(value.getType() == XmlRpcValue::TypeArray, name,
        std::string("has the wrong type (a list of strings expected, not ") +
            TypeName(value.getType()) + ")");
  out.clear();
  for (int i = 0; i < value.size(); ++i) {
    std::string text;
    Convert(name + "[" + std::to_string(i) + "]", value[i], text);
    out.push_back(text);
  }
}

}  // namespace aar_ros_common
