// The stereo node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <cmath>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <aar_ros_common/node_options.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/receiver_params.h>
#include <dynamic_reconfigure/config_tools.h>

#include "aar_stereo/ros/stereo_node.h"

namespace aar_stereo {

namespace {

using XmlRpc::XmlRpcValue;
using Description = StereoConfig::AbstractParamDescriptionConstPtr;

// An enum setting (an edit_method of Stereo.cfg: matcher, decimation) may be given by its
// constant's name ("sparse") as well as by its number. The constants as (name, number).
std::vector<std::pair<std::string, int>> EnumConstants(const Description& p) {
  static const std::regex constant(R"('name': '(\w+)', 'type': 'int', 'value': (-?[0-9]+))");
  std::vector<std::pair<std::string, int>> constants;
  const std::string& m = p->edit_method;
  for (auto it = std::sregex_iterator(m.begin(), m.end(), constant); it != std::sregex_iterator();
       ++it) {
    constants.emplace_back((*it)[1].str(), std::stoi((*it)[2].str()));
  }
  return constants;
}

// The number of the constant `name` of enum setting p; none if p has no such constant.
std::optional<int> EnumNumber(const Description& p, const std::string& name) {
  for (const auto& [n, v] : EnumConstants(p))
    if (n == name) return v;
  return std::nullopt;
}

// A name given for an enum setting, refused unless it is one of its constants.
void CheckEnumName(const aar_ros_common::ParamReader& params, const Description& p,
                   const std::string& name) {
  std::string names;
  for (const auto& [n, v] : EnumConstants(p)) names += (names.empty() ? "" : ", ") + n;
  params.Check(EnumNumber(p, name).has_value(), p->name,
               "must be one of " + names + " (or its number), not '" + name + "'");
}

// dynamic_reconfigure quietly clamps a setting to its range and takes the default for one of the
// wrong type, and ToStereoOptions rounds block sizes and disparity counts: at start-up each of
// these is refused by name instead (matcher 5 would otherwise become SGBM, block_size 'abc' 9).
void CheckReconfigurableSettings(const aar_ros_common::ParamReader& params) {
  for (const auto& p : StereoConfig::__getParamDescriptions__()) {
    XmlRpcValue value;
    if (!params.GetValue(p->name, value)) continue;  // unset: the default
    const auto type = value.getType();
    const bool is_int = type == XmlRpcValue::TypeInt;
    if (p->type == "int" && type == XmlRpcValue::TypeString && !EnumConstants(p).empty()) {
      CheckEnumName(params, p, static_cast<std::string&>(value));
      continue;
    }
    const bool ok_type = p->type == "int"      ? is_int
                         : p->type == "double" ? is_int || type == XmlRpcValue::TypeDouble
                         : p->type == "bool"   ? type == XmlRpcValue::TypeBoolean
                                               : type == XmlRpcValue::TypeString;
    params.Check(ok_type, p->name, "must be of type " + p->type);
    if (p->type != "int" && p->type != "double") continue;
    const double v = is_int ? static_cast<int>(value) : static_cast<double>(value);
    boost::any low, high;
    p->getValue(StereoConfig::__getMin__(), low);
    p->getValue(StereoConfig::__getMax__(), high);
    const double lo = p->type == "int" ? boost::any_cast<int>(low) : boost::any_cast<double>(low);
    const double hi = p->type == "int" ? boost::any_cast<int>(high) : boost::any_cast<double>(high);
    std::ostringstream range;
    range << "must be in [" << lo << ", " << hi << "], not " << v;
    params.Check(std::isfinite(v) && v >= lo && v <= hi, p->name, range.str());
  }
  const StereoConfig c = LoadStereoConfig(params);
  params.Check(c.block_size % 2 == 1, "block_size", "must be odd");
  params.Check(c.matcher == Stereo_semi_global || c.block_size >= 5, "block_size",
               "must be at least 5 for block matching");
  params.Check(c.prefilter_size % 2 == 1, "prefilter_size", "must be odd");
  params.Check(c.num_disparities % 16 == 0, "num_disparities", "must be a multiple of 16");
  params.Check(!c.organized || c.decimation == Stereo_none, "organized",
               "needs decimation none (a decimated cloud has no image shape)");
  // What the matcher itself refuses (e.g. the sparse matcher's 128 disparities), named at start-up.
  StereoConfig adjusted = c;
  try {
    StereoProcessor processor(ToStereoOptions(adjusted));
  } catch (const std::invalid_argument& e) {
    params.Check(false, "matcher", std::string("settings refused: ") + e.what());
  }
}

}  // namespace

StereoNodeOptions LoadStereoNodeOptions(const ros::NodeHandle& nh) {
  aar_ros_common::ParamReader params(nh);
  StereoNodeOptions o = LoadStereoNodeOptions(params);
  // dynamic_reconfigure's server reads its settings from the parameter server as numbers (a name
  // would quietly become the default): an enum setting given by name is written back as its number.
  for (const auto& p : StereoConfig::__getParamDescriptions__()) {
    std::string name;
    if (p->type != "int" || !nh.getParam(p->name, name)) continue;
    if (const auto number = EnumNumber(p, name)) nh.setParam(p->name, *number);
  }
  return o;
}

StereoNodeOptions LoadStereoNodeOptions(aar_ros_common::ParamReader& params) {
  StereoNodeOptions o;
  o.approximate_sync = params.Get("approximate_sync", o.approximate_sync);
  o.max_pair_skew = params.GetNonNegative("max_pair_skew", o.max_pair_skew);
  o.opencv_threads = params.Get("opencv_threads", o.opencv_threads);
  o.max_frame_age = params.Get("max_frame_age", o.max_frame_age);
  params.Check(o.max_frame_age >= 0.0, "max_frame_age", "must be >= 0 [s] (0: off)");
  o.max_stamp_lead = params.GetNonNegative("max_stamp_lead", o.max_stamp_lead);
  o.rectified_upstream = params.Get("rectified_upstream", o.rectified_upstream);
  o.queue_size = params.Get("queue_size", o.queue_size);
  o.newest_wins = params.Get("newest_wins", o.newest_wins);
  params.Check(o.queue_size >= 1, "queue_size", "must be at least 1");
  StereoRoiOptions& roi = o.roi;
  roi.enabled = params.Get("roi", roi.enabled);
  roi.margin = params.Get("roi_margin", roi.margin);
  params.Check(roi.margin >= 0, "roi_margin", "must be >= 0 [px]");
  roi.receiver_margin = params.Get("roi_receiver_margin", roi.receiver_margin);
  params.Check(roi.receiver_margin >= 0.0, "roi_receiver_margin", "must be >= 0 [m]");
  roi.include_boom = params.Get("roi_include_boom", roi.include_boom);
  roi.estimate_wait = params.GetNonNegative("estimate_wait", roi.estimate_wait);
  roi.receiver = aar_ros_common::LoadReceiver(params);
  // diagnostic_period is also read by diagnostic_updater itself.
  o.common = aar_ros_common::LoadCommonNodeOptions(params, o.common);
  // Everything else in ~ must be a reconfigurable setting (dynamic_reconfigure reads those): a
  // typo would otherwise be ignored.
  for (const auto& p : StereoConfig::__getParamDescriptions__()) params.Allow(p->name);
  CheckReconfigurableSettings(params);
  params.AllowSubNamespaces();  // dynamic_reconfigure's own
  params.RejectUnknown();
  return o;
}

StereoConfig LoadStereoConfig(const aar_ros_common::ParamReader& params) {
  // As a reconfigure request: each set key of the setting's type (or an int for a double).
  dynamic_reconfigure::Config request;
  for (const auto& p : StereoConfig::__getParamDescriptions__()) {
    XmlRpcValue v;
    if (!params.GetValue(p->name, v)) continue;
    const auto type = v.getType();
    const std::optional<int> named = p->type == "int" && type == XmlRpcValue::TypeString
                                         ? EnumNumber(p, static_cast<std::string&>(v))
                                         : std::nullopt;
    if (named) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name, *named);
    } else if (p->type == "int" && type == XmlRpcValue::TypeInt) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name, static_cast<int&>(v));
    } else if (p->type == "double" && type == XmlRpcValue::TypeInt) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name,
                                                        static_cast<double>(static_cast<int&>(v)));
    } else if (p->type == "double" && type == XmlRpcValue::TypeDouble) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name, static_cast<double&>(v));
    } else if (p->type == "bool" && type == XmlRpcValue::TypeBoolean) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name, static_cast<bool&>(v));
    } else if (p->type == "str" && type == XmlRpcValue::TypeString) {
      dynamic_reconfigure::ConfigTools::appendParameter(request, p->name,
                                                        static_cast<std::string&>(v));
    }
  }
  StereoConfig c = StereoConfig::__getDefault__();
  c.__fromMessage__(request);
  return c;
}

StereoOptions ToStereoOptions(StereoConfig& c) {
  c.block_size |= 1;  // odd
  if (c.matcher != Stereo_semi_global && c.block_size < 5) c.block_size = 5;
  c.prefilter_size |= 1;
  c.num_disparities = ((c.num_disparities + 15) / 16) * 16;
  StereoOptions o;
  o.matcher = c.matcher == Stereo_semi_global ? Matcher::kSemiGlobal
              : c.matcher == Stereo_sparse    ? Matcher::kSparse
                                              : Matcher::kBlockMatching;
  o.sparse_budget = c.sparse_budget;
  o.sparse_lr_max_diff = c.sparse_lr_max_diff;
  o.block_size = c.block_size;
  o.num_disparities = c.num_disparities;
  o.min_disparity = c.min_disparity;
  o.prefilter_size = c.prefilter_size;
  o.prefilter_cap = c.prefilter_cap;
  o.texture_threshold = c.texture_threshold;
  o.uniqueness_ratio = c.uniqueness_ratio;
  o.speckle_window_size = c.speckle_window_size;
  o.speckle_range = c.speckle_range;
  o.disp12_max_diff = c.disp12_max_diff;
  o.sgbm_p1 = c.sgbm_p1;
  o.sgbm_p2 = c.sgbm_p2;
  o.sgbm_full_dp = c.sgbm_full_dp;
  c.median_filter = c.median_filter <= 0 ? 0 : c.median_filter <= 3 ? 3 : 5;
  o.median_filter = c.median_filter;
  o.max_range = c.max_range;
  o.decimation = c.decimation == Stereo_none         ? Decimation::kNone
                 : c.decimation == Stereo_voxel_grid ? Decimation::kVoxelGrid
                                                     : Decimation::kEveryNth;
  o.keep_every = c.keep_every;
  o.voxel_size = c.voxel_size;
  if (c.organized && o.decimation != Decimation::kNone) c.organized = false;
  o.organized = c.organized;
  o.intensity = c.intensity;
  return o;
}

}  // namespace aar_stereo
