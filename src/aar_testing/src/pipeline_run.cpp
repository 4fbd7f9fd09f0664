#include "aar_testing/pipeline_run.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "aar_testing/command.h"
#include "aar_testing/paths.h"

namespace aar_testing {

PipelineRun RunPipeline(const std::string& tag, const std::string& args, double timeout_s) {
  PipelineRun run;
  run.output_dir = (std::filesystem::temp_directory_path() /
                    ("aar_pipeline_" + std::to_string(getpid()) + "_" + tag))
                       .string();
  std::filesystem::remove_all(run.output_dir);
  std::filesystem::create_directories(run.output_dir);
  const int port = FreeRosPort();
  if (port <= 0) {
    run.error = "no free port for a ROS master";
    return run;
  }
  std::ostringstream command;
  command << "ROS_MASTER_URI=http://localhost:" << port << " timeout --signal=INT --kill-after=20 "
          << timeout_s << " roslaunch -p " << port << " " << WorkspaceRoot()
          << "/launch/pipeline.launch " << args << " output_dir:=" << run.output_dir << " > "
          << run.output_dir << ".log 2>&1";
  run.status = std::system(command.str().c_str());
  std::ifstream log(run.output_dir + ".log");
  run.log.assign(std::istreambuf_iterator<char>(log), std::istreambuf_iterator<char>());
  std::ifstream csv(run.output_dir + "/frames.csv");
  if (!csv.good())
    run.error = run.output_dir + "/frames.csv missing (log: " + run.output_dir + ".log)";
  std::string line;
  std::getline(csv, line);  // t,range_m,region,estimated,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,...
  int least_column = -1;    // visible_fraction_least, by name
  {
    std::stringstream header(line);
    int i = 0;
    for (std::string name; std::getline(header, name, ','); ++i)
      if (name == "visible_fraction_least") least_column = i;
  }
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) f.push_back(cell);
    if (f.size() < 10) continue;
    PipelineFrame e;
    e.t = std::stod(f[0]);
    e.range_m = std::stod(f[1]);
    e.estimated = f[3] == "1";
    if (least_column >= 0 && least_column < static_cast<int>(f.size()) && !f[least_column].empty())
      e.visible_fraction_least = std::stod(f[least_column]);
    if (e.estimated) {
      e.position_m = {std::stod(f[4]), std::stod(f[5]), std::stod(f[6])};
      e.rpy_deg = {std::stod(f[7]), std::stod(f[8]), std::stod(f[9])};
      ++run.estimated;
      run.mean_position_m += e.position_m.norm();
      run.mean_rotation_deg += e.rpy_deg.norm();
    }
    run.frames.push_back(e);
  }
  if (run.estimated > 0) {
    run.mean_position_m /= run.estimated;
    run.mean_rotation_deg /= run.estimated;
  }
  std::printf(
      "[ pipeline ] %s (%s): status %d, %d of %zu frames estimated, mean error %.4f m, "
      "%.3f deg\n",
      tag.c_str(), args.c_str(), run.status, run.estimated, run.frames.size(), run.mean_position_m,
      run.mean_rotation_deg);
  return run;
}

}  // namespace aar_testing
