#include "aar_ros_common/node_options.h"

#include <cctype>

namespace aar_ros_common {

CommonNodeOptions LoadCommonNodeOptions(ParamReader& params, const CommonNodeOptions& defaults) {
  CommonNodeOptions o = defaults;
  o.frames = LoadStackFrames(params, defaults.frames);
  o.robot_description = params.Get("robot_description", o.robot_description);
  o.tf_timeout = params.GetNonNegative("tf_timeout", o.tf_timeout);
  o.tf_fallback_age = params.GetNonNegative("tf_fallback_age", o.tf_fallback_age);
  o.diagnostic_period = params.GetPositive("diagnostic_period", o.diagnostic_period);
  if (defaults.estimate_max_age > 0.0) {
    o.estimate_max_age = params.GetPositive("estimate_max_age", o.estimate_max_age);
    o.rig = params.Get("rig", o.rig);
    params.Check(o.rig.empty() || IsRigName(o.rig), "rig",
                 "must be a rig's name ([A-Za-z][A-Za-z0-9_]*) or empty (the first rig), not '" +
                     o.rig + "'");
  }
  return o;
}

bool IsRigName(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace aar_ros_common
