#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <aar_ros_common/start_failure.h>

#include "aar_registration/ros/registration_node.h"

namespace aar_registration {

class RegistrationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ =
          std::make_unique<RegistrationNode>(getMTNodeHandle(), getMTPrivateNodeHandle(),
                                             LoadRegistrationNodeOptions(getPrivateNodeHandle()));
    } catch (const std::exception& e) {
      aar_ros_common::EndProcessOnStartFailure("registration", e);
    }
  }
  std::unique_ptr<RegistrationNode> node_;
};

}  // namespace aar_registration

PLUGINLIB_EXPORT_CLASS(aar_registration::RegistrationNodelet, nodelet::Nodelet)
