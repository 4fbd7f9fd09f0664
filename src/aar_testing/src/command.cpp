#include "aar_testing/command.h"

#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "aar_testing/paths.h"

namespace aar_testing {

CommandResult RunCommand(const std::string& command) {
  const auto start = std::chrono::steady_clock::now();
  CommandResult r;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(("(" + command + ") 2>&1").c_str(), "r"),
                                             pclose);
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe.get())) r.output += buffer.data();
  const int status = pclose(pipe.release());
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

int FreeRosPort() {
  const CommandResult r = RunCommand(WorkspaceRoot() + "/scripts/ros-port");
  try {
    return r.status == 0 ? std::stoi(r.output) : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

}  // namespace aar_testing
