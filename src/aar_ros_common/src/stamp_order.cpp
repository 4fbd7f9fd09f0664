#include "aar_ros_common/stamp_order.h"

#include <iomanip>
#include <sstream>

namespace aar_ros_common {

std::string StampOrder::Check(const ros::Time& stamp, const ros::Time& now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (any_ && stamp <= last_stamp_ && now >= clock_at_last_) {
    ++dropped_;
    std::ostringstream s;
    s << "stamp " << stamp;
    if (stamp == last_stamp_)
      s << " repeats the last one taken";
    else
      s << " is " << std::fixed << std::setprecision(3) << (last_stamp_ - stamp).toSec()
        << " s before the last one taken, " << last_stamp_;
    s << ": out of order";
    return s.str();
  }
  any_ = true;
  last_stamp_ = stamp;
  clock_at_last_ = now;
  return "";
}

}  // namespace aar_ros_common
