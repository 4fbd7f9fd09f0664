#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <aar_ros_common/start_failure.h>

#include "aar_stereo/ros/stereo_node.h"

namespace aar_stereo {

// aar_stereo inside a nodelet manager: zero-copy images from a camera or simulator nodelet.
class StereoNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ = std::make_unique<StereoNode>(getMTNodeHandle(), getMTPrivateNodeHandle(),
                                           LoadStereoNodeOptions(getPrivateNodeHandle()));
    } catch (const std::exception& e) {
      aar_ros_common::EndProcessOnStartFailure("stereo", e);
    }
  }
  std::unique_ptr<StereoNode> node_;
};

}  // namespace aar_stereo

PLUGINLIB_EXPORT_CLASS(aar_stereo::StereoNodelet, nodelet::Nodelet)
