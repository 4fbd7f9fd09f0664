// Fuzz target params: a YAML file as `rosparam load` puts it on the parameter server, read by
// every node's option loader through aar_ros_common::ParamReader (over the parameter tree, no
// master). The file is loaded twice, as the launch files load the two kinds in config/: at the
// root (an experiment: sim:, stereo: aar_stereo:, occlusion:, registration:) and into each node's
// namespace (a node file such as stereo.yaml); then, as launch/pipeline.launch does,
// sim/flight_path and eval/output_dir are set. A loader may refuse with std::invalid_argument.
// Options a loader accepted must then work: the stereo matcher settings give a valid matcher.
//
// YAML to XmlRpc as rosparam (PyYAML, YAML 1.1) does: plain scalars resolve to bool, int, float
// or null by YAML 1.1's patterns, quoted ones stay strings; maps are namespaces. What rosparam
// cannot send is refused as rosparam refuses it: null, ints beyond 32 bits, non-scalar keys.
// Not modelled: rosparam's !degrees/!radians and deg()/rad(), binary and timestamps (strings).
#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <aar_eval/ros/eval_node.h>
#include <aar_occlusion/ros/occlusion_node.h>
#include <aar_registration/ros/registration_node.h>
#include <aar_ros_common/param_reader.h>
#include <aar_sim/ros/sim_node.h>
#include <aar_stereo/ros/stereo_node.h>
#include <yaml-cpp/yaml.h>

#include "fuzz_support.h"

namespace {

using XmlRpc::XmlRpcValue;

// Input that rosparam would not load either.
struct NotLoadable {};

std::string WithoutUnderscores(std::string s) {
  s.erase(std::remove(s.begin(), s.end(), '_'), s.end());
  return s;
}

// An empty map, replacing whatever `value` was.
void MakeMap(XmlRpcValue& value) {
  if (value.getType() == XmlRpcValue::TypeStruct) return;
  value = XmlRpcValue();
  value.begin();  // an invalid value becomes a struct
}

// YAML 1.1 sexagesimal "1:30:05" (base 60) after an optional sign.
double Sexagesimal(const std::string& text) {
  double value = 0.0;
  const bool negative = text[0] == '-';
  std::stringstream parts(text.substr(text[0] == '-' || text[0] == '+'));
  for (std::string part; std::getline(parts, part, ':');) value = value * 60 + std::stod(part);
  return negative ? -value : value;
}

XmlRpcValue Scalar(const YAML::Node& node) {
  const std::string& text = node.Scalar();
  if (node.Tag() != "?") return XmlRpcValue(text);  // quoted ("!") or explicitly tagged
  // PyYAML's implicit resolvers (yaml/resolver.py).
  static const std::regex kBool(
      "yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF");
  static const std::regex kNull("~|null|Null|NULL|");
  static const std::regex kInt(
      "[-+]?0b[0-1_]+|[-+]?0[0-7_]+|[-+]?(0|[1-9][0-9_]*)|[-+]?0x[0-9a-fA-F_]+|"
      "[-+]?[1-9][0-9_]*(:[0-5]?[0-9])+");
  static const std::regex kFloat(
      "[-+]?[0-9][0-9_]*\\.[0-9_]*([eE][-+][0-9]+)?|\\.[0-9][0-9_]*([eE][-+][0-9]+)?|"
      "[-+]?[0-9][0-9_]*(:[0-5]?[0-9])+\\.[0-9_]*|[-+]?\\.(inf|Inf|INF)|\\.(nan|NaN|NAN)");
  if (std::regex_match(text, kBool)) {
    const char c = text[0];
    return XmlRpcValue(c == 'y' || c == 'Y' || c == 't' || c == 'T' ||
                       ((c == 'o' || c == 'O') && (text[1] == 'n' || text[1] == 'N')));
  }
  if (std::regex_match(text, kNull)) throw NotLoadable{};  // xmlrpc cannot send None
  if (std::regex_match(text, kInt)) {
    const std::string digits = WithoutUnderscores(text);
    double value = 0.0;
    if (digits.find(':') != std::string::npos) {
      value = Sexagesimal(digits);
    } else {
      const size_t sign = digits[0] == '-' || digits[0] == '+';
      const std::string body = digits.substr(sign);
      int base = 10;
      size_t skip = 0;
      if (body.rfind("0b", 0) == 0)
        base = 2, skip = 2;
      else if (body.rfind("0x", 0) == 0)
        base = 16, skip = 2;
      else if (body.size() > 1 && body[0] == '0')
        base = 8, skip = 1;
      if (body.size() == skip) throw NotLoadable{};  // "0x": Python's int() refuses it
      errno = 0;
      const unsigned long long magnitude = std::strtoull(body.c_str() + skip, nullptr, base);
      if (errno == ERANGE) throw NotLoadable{};
      value = static_cast<double>(magnitude) * (digits[0] == '-' ? -1 : 1);
    }
    if (value < INT_MIN || value > INT_MAX) throw NotLoadable{};  // xmlrpc's int is 32 bits
    return XmlRpcValue(static_cast<int>(value));
  }
  if (std::regex_match(text, kFloat)) {
    const std::string digits = WithoutUnderscores(text);
    if (digits.find("inf") != std::string::npos || digits.find("Inf") != std::string::npos ||
        digits.find("INF") != std::string::npos)
      return XmlRpcValue(digits[0] == '-' ? -HUGE_VAL : HUGE_VAL);
    if (digits.find("nan") != std::string::npos || digits.find("NaN") != std::string::npos ||
        digits.find("NAN") != std::string::npos)
      return XmlRpcValue(std::nan(""));
    if (digits.find(':') != std::string::npos) return XmlRpcValue(Sexagesimal(digits));
    return XmlRpcValue(std::strtod(digits.c_str(), nullptr));
  }
  return XmlRpcValue(text);
}

// Bounds the work: an alias can repeat a subtree exponentially often.
XmlRpcValue ToXmlRpc(const YAML::Node& node, int depth, int& budget) {
  if (depth > 64 || --budget < 0) throw NotLoadable{};
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return Scalar(node);
    case YAML::NodeType::Sequence: {
      XmlRpcValue array;
      array.setSize(0);
      int i = 0;
      for (const auto& item : node) array[i++] = ToXmlRpc(item, depth + 1, budget);
      return array;
    }
    case YAML::NodeType::Map: {
      XmlRpcValue map;
      MakeMap(map);  // an empty map is a struct too
      for (const auto& item : node) {
        // xmlrpc's keys are strings: not a map or list, nor a plain 1, true or 2.5.
        if (!item.first.IsScalar() || Scalar(item.first).getType() != XmlRpcValue::TypeString)
          throw NotLoadable{};
        map[item.first.Scalar()] = ToXmlRpc(item.second, depth + 1, budget);
      }
      return map;
    }
    default:
      throw NotLoadable{};  // null, undefined
  }
}

// tree[path...] = value, creating namespaces (rosparam set / a launch file's <param>).
void Set(XmlRpcValue& tree, const std::vector<std::string>& path, const XmlRpcValue& value) {
  XmlRpcValue* node = &tree;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    MakeMap(*node);
    node = &(*node)[path[i]];
  }
  MakeMap(*node);
  (*node)[path.back()] = value;
}

// What launch/pipeline.launch sets besides the YAML files.
void SetLaunchParameters(XmlRpcValue& tree) {
  Set(tree, {"sim", "flight_path"}, XmlRpcValue("approach_default.csv"));
  Set(tree, {"eval", "output_dir"}, XmlRpcValue("/tmp/aar_fuzz_results"));
}

// Each node's loader on the tree. What a loader accepted must be usable: the simulator's rig and
// clock finite, the stereo settings a valid matcher, the registration's nominal pose finite.
void LoadEveryNode(const XmlRpcValue& tree) {
  try {
    aar_ros_common::ParamReader params(tree, "/sim");
    const aar_sim::SimNodeOptions o = aar_sim::LoadSimNodeOptions(params);
    const aar_sim::StereoRig& rig = o.world.rig;
    FUZZ_CHECK(rig.T_tanker_left_optical.matrix().allFinite() && std::isfinite(rig.baseline) &&
                   std::isfinite(rig.intrinsics.fx) && std::isfinite(rig.intrinsics.cx),
               "the simulator accepted a rig that is not finite");
    for (const double v : {o.rate, o.start_time, o.lockstep_timeout, o.start_delay, o.stamp_offset,
                           o.world.sensor.noise_stddev, o.world.renderer.sky_level,
                           o.world.sensor.full_well, o.world.sensor.exposure_time,
                           o.world.sensor.gain_mismatch, o.world.sensor.exposure_target,
                           o.world.sensor.exposure_gain_min, o.world.sensor.exposure_gain_max})
      FUZZ_CHECK(std::isfinite(v), "the simulator accepted a setting that is not finite");
  } catch (const std::invalid_argument&) {
  }
  std::optional<aar_stereo::StereoConfig> stereo;
  try {
    aar_ros_common::ParamReader params(tree, "/stereo/aar_stereo");
    aar_stereo::LoadStereoNodeOptions(params);
    stereo = aar_stereo::LoadStereoConfig(params);
  } catch (const std::invalid_argument&) {
  }
  if (stereo) {
    stereo->__clamp__();  // as dynamic_reconfigure's server starts
    const aar_stereo::StereoOptions options = aar_stereo::ToStereoOptions(*stereo);
    aar_stereo::StereoProcessor processor(options);  // throws: a finding
  }
  try {
    aar_ros_common::ParamReader params(tree, "/occlusion");
    aar_occlusion::LoadOcclusionNodeOptions(params);
  } catch (const std::invalid_argument&) {
  }
  try {
    aar_ros_common::ParamReader params(tree, "/registration");
    const auto o = aar_registration::LoadRegistrationNodeOptions(params);
    FUZZ_CHECK(o.registrar.T_tanker_receiver_nominal.matrix().allFinite(),
               "registration accepted a nominal pose that is not finite");
  } catch (const std::invalid_argument&) {
  }
  try {
    aar_ros_common::ParamReader params(tree, "/eval");
    aar_eval::LoadEvalNodeOptions(params);
  } catch (const std::invalid_argument&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  XmlRpcValue file;
  try {
    int budget = 100000;
    file = ToXmlRpc(YAML::Load(std::string(reinterpret_cast<const char*>(data), size)), 0, budget);
  } catch (const YAML::Exception&) {
    return 0;
  } catch (const NotLoadable&) {
    return 0;
  }
  if (file.getType() != XmlRpcValue::TypeStruct) return 0;  // rosparam loads maps only

  XmlRpcValue root = file;  // an experiment, loaded at the root
  SetLaunchParameters(root);
  LoadEveryNode(root);

  XmlRpcValue nodes;  // a node file, loaded into each node's namespace
  for (const std::vector<std::string>& ns : {std::vector<std::string>{"sim"},
                                             {"stereo", "aar_stereo"},
                                             {"occlusion"},
                                             {"registration"},
                                             {"eval"}})
    Set(nodes, ns, file);
  SetLaunchParameters(nodes);
  LoadEveryNode(nodes);
  return 0;
}
