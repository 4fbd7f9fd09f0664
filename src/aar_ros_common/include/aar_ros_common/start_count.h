#pragma once

#include <string>

#include <ros/node_handle.h>

namespace aar_ros_common {

// Counts the starts of a node under one master (parameter /aar_starts/<node name>) and logs the
// start: INFO the first time, WARN from the second on, so that a node respawned after it died
// says so on /rosout, not only on roslaunch's screen. `stage` prefixes the message ("stereo").
// Returns the count.
int AnnounceStart(const ros::NodeHandle& private_nh, const std::string& stage);

}  // namespace aar_ros_common
