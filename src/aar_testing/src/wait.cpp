#include "aar_testing/wait.h"

#include <ros/ros.h>

namespace aar_testing {

bool WaitFor(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (!done()) {
    if (ros::WallTime::now() > deadline || !ros::ok()) return done();
    ros::WallDuration(0.01).sleep();
  }
  return true;
}

}  // namespace aar_testing
