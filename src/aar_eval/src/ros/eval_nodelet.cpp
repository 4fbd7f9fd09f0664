#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <aar_ros_common/start_failure.h>

#include "aar_eval/ros/eval_node.h"

namespace aar_eval {

class EvalNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ = std::make_unique<EvalNode>(getMTNodeHandle(),
                                         LoadEvalNodeOptions(getPrivateNodeHandle()));
    } catch (const std::exception& e) {
      aar_ros_common::EndProcessOnStartFailure("eval", e);
    }
  }
  std::unique_ptr<EvalNode> node_;
};

}  // namespace aar_eval

PLUGINLIB_EXPORT_CLASS(aar_eval::EvalNodelet, nodelet::Nodelet)
