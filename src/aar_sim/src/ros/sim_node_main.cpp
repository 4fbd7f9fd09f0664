// sim_node: the simulator as a standalone process. Exits non-zero, saying why, when the flight
// path, a model or EGL is missing or bad, or rendering fails.
#include <unistd.h>
#include <csignal>

#include <atomic>

#include <ros/ros.h>

#include "aar_sim/ros/sim_node.h"

namespace {

std::atomic<bool> g_started{false};

// SIGINT while the world is still being built (meshes, EGL, shaders: seconds) ends the process
// at once: roscpp's handler only asks for a shutdown, seen once construction is over, and a
// launch ending for another reason (a stage that refused to start) waited for it.
void OnSigint(int) {
  if (!g_started) _exit(130);
  ros::requestShutdown();
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "sim", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, OnSigint);
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<aar_sim::SimNode> node;
  try {
    node = std::make_unique<aar_sim::SimNode>(nh, aar_sim::LoadSimNodeOptions(pnh));
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("sim: " << e.what());
    return 1;
  }
  g_started = true;
  node->Start();
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // Until ros::shutdown (shutdown_at_end, a signal) or a failed frame loop, which must not exit
  // 0 like a finished run: launch/sim.launch ends a clean exit quietly.
  while (ros::ok() && !node->failed()) ros::WallDuration(0.1).sleep();
  return node->failed() ? 1 : 0;
}
