#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <aar_ros_common/start_failure.h>

#include "aar_occlusion/ros/occlusion_node.h"

namespace aar_occlusion {

class OcclusionNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ = std::make_unique<OcclusionNode>(getMTNodeHandle(), getMTPrivateNodeHandle(),
                                              LoadOcclusionNodeOptions(getPrivateNodeHandle()));
    } catch (const std::exception& e) {
      aar_ros_common::EndProcessOnStartFailure("occlusion", e);
    }
  }
  std::unique_ptr<OcclusionNode> node_;
};

}  // namespace aar_occlusion

PLUGINLIB_EXPORT_CLASS(aar_occlusion::OcclusionNodelet, nodelet::Nodelet)
