#pragma once

#include <functional>

namespace aar_testing {

// Polls `done` every 10 ms of wall time until it holds or `timeout_s` passes (or ROS shuts down);
// returns its last value. Wall time: simulated time may stand still in lockstep.
bool WaitFor(const std::function<bool()>& done, double timeout_s);

}  // namespace aar_testing
