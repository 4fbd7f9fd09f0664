// The node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/receiver_params.h>

#include "aar_occlusion/ros/occlusion_node.h"

namespace aar_occlusion {

OcclusionNodeOptions LoadOcclusionNodeOptions(const ros::NodeHandle& nh) {
  aar_ros_common::ParamReader params(nh);
  return LoadOcclusionNodeOptions(params);
}

OcclusionNodeOptions LoadOcclusionNodeOptions(aar_ros_common::ParamReader& params) {
  OcclusionNodeOptions o;
  OcclusionStepOptions& step = o.step;
  step.cull = ParseCullMethod(params.Get<std::string>("cull", ToString(step.cull)));
  step.parts.cull_margin = params.Get("cull_margin", step.parts.cull_margin);
  step.parts.silhouette_margin = params.Get("silhouette_margin", step.parts.silhouette_margin);
  if (!(step.parts.cull_margin >= 0.0) || !(step.parts.silhouette_margin >= 0.0))
    throw std::invalid_argument("~cull_margin and ~silhouette_margin must be >= 0");
  step.boom.cull_behind_boom = params.Get("cull_behind_boom", step.boom.cull_behind_boom);
  step.boom.cull_depth_coefficient =
      params.GetNonNegative("cull_depth_coefficient", step.boom.cull_depth_coefficient);
  step.model_boom = params.Get("model_boom", step.model_boom);
  step.build_reference = params.Get("publish_reference", step.build_reference);
  o.robot_description = params.Get("robot_description", o.robot_description);
  o.receiver = aar_ros_common::LoadReceiverModel(params, step.sampling);
  for (const auto& p : o.receiver.propellers)  // the description's, for cull_propellers
    step.propellers.push_back({p.hub, p.axis, p.radius, p.hub_radius});
  // Sampling does not cast rays here: the tolerance is the dynamic reference's self-occlusion.
  step.reference.visibility_tolerance = step.sampling.visibility_tolerance;
  step.reference.reshell_distance = params.Get("reshell_distance", step.reference.reshell_distance);
  step.max_point_range = params.Get("max_point_range", step.max_point_range);
  step.seed_densest_ball =
      params.GetChoice<bool>("seed_points", "all", {{"all", false}, {"densest_ball", true}});
  step.cull_propellers = params.Get("cull_propellers", step.cull_propellers);
  step.propeller_margin = params.GetNonNegative("propeller_margin", step.propeller_margin);
  step.propeller_depth_margin =
      params.GetNonNegative("propeller_depth_margin", step.propeller_depth_margin);
  step.gate_receiver = params.Get("gate_receiver", step.gate_receiver);
  step.gate_margin = params.GetNonNegative("gate_margin", step.gate_margin);
  step.gate_depth_coefficient =
      params.GetNonNegative("gate_depth_coefficient", step.gate_depth_coefficient);
  params.Check(step.max_point_range > 0.0, "max_point_range", "must be > 0");
  o.frames = aar_ros_common::LoadStackFrames(params);
  o.tf_timeout = params.GetNonNegative("tf_timeout", o.tf_timeout);
  o.tf_fallback_age = params.GetNonNegative("tf_fallback_age", o.tf_fallback_age);
  o.newest_wins = params.Get("newest_wins", o.newest_wins);
  o.estimate_max_age = params.Get("estimate_max_age", o.estimate_max_age);
  o.marker_length = params.Get("marker_length", o.marker_length);
  o.estimate_wait = params.GetNonNegative("estimate_wait", o.estimate_wait);
  o.extrapolate_estimate = params.Get("extrapolate_estimate", o.extrapolate_estimate);
  o.diagnostic_period = params.Get("diagnostic_period", o.diagnostic_period);
  if (!(o.diagnostic_period > 0.0)) throw std::invalid_argument("~diagnostic_period must be > 0");
  params.RejectUnknown();
  return o;
}

}  // namespace aar_occlusion
