// The node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <aar_ros_common/param_reader.h>

#include "aar_eval/ros/eval_node.h"

namespace aar_eval {

EvalNodeOptions LoadEvalNodeOptions(const ros::NodeHandle& nh) {
  aar_ros_common::ParamReader params(nh);
  return LoadEvalNodeOptions(params);
}

EvalNodeOptions LoadEvalNodeOptions(aar_ros_common::ParamReader& params) {
  EvalNodeOptions o;
  o.output_dir = params.Required("output_dir", "where frames.csv goes");
  // The simulator's stamp offset, read where it is configured unless given here.
  const double sim_offset = params.Get("/sim/stamp_offset", o.stamp_offset);
  o.stamp_offset = params.Get("stamp_offset", sim_offset);
  o.expected_frames = params.Get("expected_frames", o.expected_frames);
  o.settle_after = params.GetPositive("settle_after", o.settle_after);
  o.estimate_publisher = params.Get("estimate_publisher", o.estimate_publisher);
  o.truth_tolerance = params.GetNonNegative("truth_tolerance", o.truth_tolerance);
  o.truth_frame = params.Get("truth_frame", o.truth_frame);
  o.tanker_frame = params.Get("tanker_frame", o.tanker_frame);
  o.rigs = params.Get("rigs", o.rigs);
  params.Check(!o.rigs.empty(), "rigs", "must name at least one rig");
  params.RejectUnknown();
  return o;
}

}  // namespace aar_eval
