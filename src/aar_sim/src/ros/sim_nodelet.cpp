#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <aar_ros_common/start_failure.h>

#include "aar_sim/ros/sim_node.h"

namespace aar_sim {

// The simulator inside a nodelet manager. Start-up errors are logged as fatal and leave the
// nodelet idle (a manager process is shared, so it is not ended).
class SimNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      node_ =
          std::make_unique<SimNode>(getMTNodeHandle(), LoadSimNodeOptions(getPrivateNodeHandle()));
      node_->Start();
    } catch (const std::exception& e) {
      aar_ros_common::EndProcessOnStartFailure("sim", e);
    }
  }
  std::unique_ptr<SimNode> node_;
};

}  // namespace aar_sim

PLUGINLIB_EXPORT_CLASS(aar_sim::SimNodelet, nodelet::Nodelet)
