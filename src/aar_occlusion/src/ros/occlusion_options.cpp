// The node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <aar_ros_common/node_options.h>
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
  o.receiver = aar_ros_common::LoadReceiverModel(params, step.sampling);
  for (const auto& p : o.receiver.propellers)  // the description's, for cull_propellers
    step.propellers.push_back({p.hub, p.axis, p.radius, p.hub_radius});
  step.reference.reshell_distance = params.Get("reshell_distance", step.reference.reshell_distance);
  step.max_point_range = params.Get("max_point_range", step.max_point_range);
  step.seed_points = aar_ros_common::LoadSeedPoints(params);
  step.cull_propellers = params.Get("cull_propellers", step.cull_propellers);
  step.propeller_margin = params.GetNonNegative("propeller_margin", step.propeller_margin);
  step.propeller_depth_margin =
      params.GetNonNegative("propeller_depth_margin", step.propeller_depth_margin);
  step.gate_receiver = params.Get("gate_receiver", step.gate_receiver);
  step.gate_margin = params.GetNonNegative("gate_margin", step.gate_margin);
  step.gate_depth_coefficient =
      params.GetNonNegative("gate_depth_coefficient", step.gate_depth_coefficient);
  params.Check(step.max_point_range > 0.0, "max_point_range", "must be > 0");
  o.common = aar_ros_common::LoadCommonNodeOptions(params, o.common);
  o.newest_wins = params.Get("newest_wins", o.newest_wins);
  o.marker_length = params.Get("marker_length", o.marker_length);
  o.estimate_wait = params.GetNonNegative("estimate_wait", o.estimate_wait);
  o.extrapolate_estimate = params.Get("extrapolate_estimate", o.extrapolate_estimate);
  params.RejectUnknown();
  return o;
}

}  // namespace aar_occlusion
