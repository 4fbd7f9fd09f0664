#pragma once

#include <string>

namespace aar_testing {

struct CommandResult {
  int status = -1;       // the exit code; -1 when killed by a signal
  std::string output;    // stdout and stderr, interleaved
  double seconds = 0.0;  // [s wall]
};

// Runs `command` through /bin/sh with stderr joined to stdout, and waits for it.
CommandResult RunCommand(const std::string& command);

// A free port for a ROS master of the caller's own (scripts/ros-port); 0 if none was found.
int FreeRosPort();

}  // namespace aar_testing
