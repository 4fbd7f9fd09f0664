#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace aar_testing {

// One frame of a pipeline run's frames.csv (aar_eval).
struct PipelineFrame {
  double t = 0.0;        // [s] path time
  double range_m = 0.0;  // [m] the receiver's true range
  bool estimated = false;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // error along the true receiver axes
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();     // roll, pitch, yaw of the error
  // The simulator's: the share of the receiver the weaker camera of the best rig sees (NaN: not
  // measured).
  double visible_fraction_least = std::numeric_limits<double>::quiet_NaN();
};

struct PipelineRun {
  int status = -1;  // roslaunch's (through timeout): 0 when the run ended by itself
  std::vector<PipelineFrame> frames;
  int estimated = 0;
  double mean_position_m = 0.0, mean_rotation_deg = 0.0;  // over the estimated frames
  std::string log;                                        // roslaunch's output
  std::string output_dir;
  std::string error;  // empty, or why there are no frames (no port, no frames.csv)
};

// launch/pipeline.launch with `args` (experiment:=, frames:=, start_time:=, sim_config:=, ...) on
// a ROS master of its own, writing into a fresh aar_pipeline_<pid>_<tag> in the temp directory
// (the log beside it); killed after `timeout_s` [s wall]. Reads its frames.csv.
PipelineRun RunPipeline(const std::string& tag, const std::string& args, double timeout_s = 240.0);

}  // namespace aar_testing
