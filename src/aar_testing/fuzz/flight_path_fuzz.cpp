// Fuzz target flight_path: a flight-path CSV through aar_sim::FlightPath::Load, with the shipped
// boom's joint limits as the simulator gives them, then sampled as the simulator samples it.
// Load may refuse a file with aar_geometry::LoadError; a path it accepts must give a finite
// state at every time.
#include <cmath>
#include <limits>
#include <optional>

#include <aar_geometry/load_error.h>
#include <aar_geometry/robot_model.h>
#include <aar_sim/flight_path.h>

#include "fuzz_support.h"

namespace {

const aar_sim::FlightPathOptions& BoomLimits() {
  static const aar_sim::FlightPathOptions options = [] {
    aar_geometry::RobotModelOptions model;
    model.package_paths = {aar_fuzz::SourceDir() + "/aar_description"};
    aar_sim::FlightPathOptions o;
    o.boom_joints = aar_geometry::LoadRobotModel(
                        aar_fuzz::SourceDir() + "/aar_description/models/boom.urdf", model)
                        .joints;
    return o;
  }();
  return options;
}

void CheckState(const aar_sim::FlightPath& path, double t) {
  const aar_sim::FlightPathRow row = path.At(t);
  const std::string at = "state at t = " + std::to_string(t);
  FUZZ_CHECK(row.position_m.allFinite(), at + ": position not finite");
  FUZZ_CHECK(
      std::isfinite(row.rpy.roll) && std::isfinite(row.rpy.pitch) && std::isfinite(row.rpy.yaw),
      at + ": attitude not finite");
  FUZZ_CHECK(row.boom.has_value() == path.has_boom(), at + ": boom pose appears or vanishes");
  if (row.boom) {
    FUZZ_CHECK(std::isfinite(row.boom->pitch) && std::isfinite(row.boom->roll) &&
                   std::isfinite(row.boom->extension),
               at + ": boom pose not finite");
  }
  const Eigen::Matrix3d R = row.T_tanker_receiver().linear();
  FUZZ_CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9,
             at + ": attitude is not a rotation");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const aar_sim::FlightPathOptions& options = BoomLimits();
  const std::string file = aar_fuzz::WriteScratch("flight_path.csv", data, size);
  std::optional<aar_sim::FlightPath> path;
  try {
    path = aar_sim::FlightPath::Load(file, options);
  } catch (const aar_geometry::LoadError&) {
    return 0;
  }
  FUZZ_CHECK(!path->rows().empty(), "a loaded path has rows");
  const double start = path->start_time(), end = path->end_time();
  // The simulator's frames run from the start to the end; before and after, the ends hold.
  for (double t : {start - 1.0, start, end, end + 1.0, std::numeric_limits<double>::quiet_NaN()})
    CheckState(*path, t);
  const auto& rows = path->rows();
  for (size_t i = 0; i + 1 < rows.size() && i < 64; ++i) {
    CheckState(*path, rows[i].t);
    CheckState(*path, rows[i].t + 0.5 * (rows[i + 1].t - rows[i].t));
  }
  return 0;
}
