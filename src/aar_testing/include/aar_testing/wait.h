#pragma once

#include <functional>

namespace aar_testing {

// Polls `done` every 10 ms of wall time until it holds, `timeout_s` passes or ROS shuts down;
// returns its last value. Not scaled by TimeScale(): some waits expect nothing to come. Wall time:
// simulated time may stand still in lockstep.
bool WaitFor(const std::function<bool()>& done, double timeout_s);

}  // namespace aar_testing
