#include "aar_ros_common/start_count.h"

#include <ros/console.h>
#include <ros/param.h>

namespace aar_ros_common {

int AnnounceStart(const ros::NodeHandle& private_nh, const std::string& stage) {
  const std::string name = private_nh.getNamespace();
  const std::string key = "/aar_starts" + name;
  int starts = 0;
  ros::param::get(key, starts);
  ros::param::set(key, ++starts);
  if (starts == 1) {
    ROS_INFO_STREAM(stage << ": " << name << " started");
  } else {
    ROS_WARN_STREAM(stage << ": " << name << " started again (start " << starts
                          << " under this master): it had stopped or died, and the frames in "
                             "between got nothing from it");
  }
  return starts;
}

}  // namespace aar_ros_common
