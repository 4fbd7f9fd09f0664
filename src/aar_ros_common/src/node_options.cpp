#include "aar_ros_common/node_options.h"

namespace aar_ros_common {

CommonNodeOptions LoadCommonNodeOptions(ParamReader& params, const CommonNodeOptions& defaults) {
  CommonNodeOptions o = defaults;
  o.frames = LoadStackFrames(params, defaults.frames);
  o.robot_description = params.Get("robot_description", o.robot_description);
  o.tf_timeout = params.GetNonNegative("tf_timeout", o.tf_timeout);
  o.tf_fallback_age = params.GetNonNegative("tf_fallback_age", o.tf_fallback_age);
  o.diagnostic_period = params.GetPositive("diagnostic_period", o.diagnostic_period);
  if (defaults.estimate_max_age > 0.0)
    o.estimate_max_age = params.GetPositive("estimate_max_age", o.estimate_max_age);
  return o;
}

}  // namespace aar_ros_common
