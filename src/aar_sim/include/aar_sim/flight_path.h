#pragma once

#include <optional>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/robot_model.h>

namespace aar_sim {

// Boom joint positions (aar_description's): the CSV's optional boom columns.
using aar_description::BoomPose;

// One row of a flight path: the receiver origin in the tanker frame.
struct FlightPathRow {
  double t = 0.0;  // [s]
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  aar_geometry::RollPitchYaw rpy;  // [rad]
  std::optional<BoomPose> boom;    // set when the file has boom columns

  Eigen::Isometry3d T_tanker_receiver() const;
};

struct FlightPathOptions {
  // The boom model's joints (e.g. World::boom_model().joints): boom columns must lie within the
  // limits of its boom_pitch, boom_roll and boom_extension (Joint::WithinLimits). Empty: not
  // checked.
  std::vector<aar_geometry::Joint> boom_joints;
};

// A receiver trajectory from a CSV with header t,x,y,z,roll,pitch,yaw (s, m, deg; intrinsic
// z-y'-x'') and optional boom_pitch,boom_roll,boom_extension (deg, deg, m), in any column order.
// Between rows, position and boom are interpolated linearly and attitude by slerp.
class FlightPath {
 public:
  // Throws aar_geometry::LoadError naming the file and line for a missing or empty file, a
  // missing column, a cell that is not a finite number, a row of the wrong width, a time that
  // does not increase, or a boom cell outside its joint's limits (naming the column and the
  // limits; a boom model without that joint is named too).
  static FlightPath Load(const std::string& path, const FlightPathOptions& options = {});
  // Throws std::invalid_argument on the same problems as Load (without file and line).
  explicit FlightPath(std::vector<FlightPathRow> rows);

  const std::vector<FlightPathRow>& rows() const { return rows_; }
  bool has_boom() const { return rows_.front().boom.has_value(); }
  double start_time() const { return rows_.front().t; }
  double end_time() const { return rows_.back().t; }

  // State at time t [s], clamped to [start_time, end_time].
  FlightPathRow At(double t) const;

 private:
  std::vector<FlightPathRow> rows_;
};

// Writes rows with the header above (boom columns when rows carry a boom pose). Throws
// aar_geometry::LoadError if the file cannot be written.
void WriteFlightPath(const std::string& path, const std::vector<FlightPathRow>& rows);

}  // namespace aar_sim
