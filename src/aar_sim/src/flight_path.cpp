#include "aar_sim/flight_path.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include <aar_geometry/load_error.h>

namespace aar_sim {
namespace {

using aar_geometry::DegToRad;
using aar_geometry::LoadError;
using aar_geometry::RadToDeg;

const std::vector<std::string> kRequired = {"t", "x", "y", "z", "roll", "pitch", "yaw"};
const std::vector<std::string> kBoom = {"boom_pitch", "boom_roll", "boom_extension"};

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const size_t b = cell.find_first_not_of(" \t\r");
    const size_t e = cell.find_last_not_of(" \t\r");
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

void CheckIncreasing(const std::vector<FlightPathRow>& rows, size_t i) {
  if (i > 0 && !(rows[i].t > rows[i - 1].t)) {
    std::ostringstream msg;
    msg << "time " << rows[i].t << " s does not increase (previous row: " << rows[i - 1].t << " s)";
    throw std::invalid_argument(msg.str());
  }
}

// The boom column's joint from `options`, or nullptr when the options name no joints.
const aar_geometry::Joint* BoomJoint(const std::string& path, const std::string& where,
                                     const FlightPathOptions& options, const std::string& name) {
  if (options.boom_joints.empty()) return nullptr;
  for (const auto& joint : options.boom_joints) {
    if (joint.name == name) return &joint;
  }
  throw LoadError(path,
                  where + "column '" + name + "': the boom model has no joint '" + name + "'");
}

}  // namespace

Eigen::Isometry3d FlightPathRow::T_tanker_receiver() const {
  return aar_geometry::MakeTransform(position_m, rpy);
}

FlightPath::FlightPath(std::vector<FlightPathRow> rows) : rows_(std::move(rows)) {
  if (rows_.empty()) throw std::invalid_argument("flight path has no rows");
  for (size_t i = 0; i < rows_.size(); ++i) {
    if (rows_[i].boom.has_value() != rows_.front().boom.has_value()) {
      throw std::invalid_argument("row " + std::to_string(i) + " differs in having a boom pose");
    }
    CheckIncreasing(rows_, i);
  }
}

FlightPath FlightPath::Load(const std::string& path, const FlightPathOptions& options) {
  aar_geometry::CheckReadableFile(path);
  std::ifstream in(path);
  std::string line;
  int line_number = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    header = SplitCsv(line);
  }
  if (header.empty()) throw LoadError(path, "no header line (expected t,x,y,z,roll,pitch,yaw)");
  const std::string where_header = "line " + std::to_string(line_number) + ": ";
  std::map<std::string, size_t> column;
  for (size_t c = 0; c < header.size(); ++c) {
    if (!column.emplace(header[c], c).second) {
      throw LoadError(path, where_header + "column '" + header[c] + "' appears twice");
    }
  }
  for (const auto& name : kRequired) {
    if (!column.count(name)) throw LoadError(path, where_header + "missing column '" + name + "'");
  }
  const int boom_columns = static_cast<int>(std::count_if(
      kBoom.begin(), kBoom.end(), [&](const std::string& n) { return column.count(n) > 0; }));
  if (boom_columns != 0 && boom_columns != 3) {
    throw LoadError(path, where_header +
                              "boom columns must be all of boom_pitch, boom_roll, "
                              "boom_extension or none");
  }

  // Boom columns: CSV name, joint, CSV unit per joint unit (deg per rad or m per m), unit name.
  struct BoomColumn {
    std::string name;
    const aar_geometry::Joint* joint;
    double scale;
    const char* unit;
  };
  std::vector<BoomColumn> boom_limits;
  if (boom_columns == 3) {
    for (const auto& name : kBoom) {
      const bool angle = name != "boom_extension";
      boom_limits.push_back({name, BoomJoint(path, where_header, options, name),
                             angle ? RadToDeg(1.0) : 1.0, angle ? " deg" : " m"});
    }
  }

  std::vector<FlightPathRow> rows;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const std::string where = "line " + std::to_string(line_number) + ": ";
    const std::vector<std::string> cells = SplitCsv(line);
    if (cells.size() != header.size()) {
      throw LoadError(path, where + std::to_string(cells.size()) + " cells, header has " +
                                std::to_string(header.size()));
    }
    auto number = [&](const std::string& name) {
      const std::string& cell = cells[column.at(name)];
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(value)) {
        throw LoadError(path,
                        where + "column '" + name + "': '" + cell + "' is not a finite number");
      }
      return value;
    };
    FlightPathRow row;
    row.t = number("t");
    row.position_m = {number("x"), number("y"), number("z")};
    row.rpy = {DegToRad(number("roll")), DegToRad(number("pitch")), DegToRad(number("yaw"))};
    if (boom_columns == 3) {
      row.boom = BoomPose{DegToRad(number("boom_pitch")), DegToRad(number("boom_roll")),
                          number("boom_extension")};
      // The joint states the sim publishes: outside the URDF's limits no real boom goes there.
      const std::map<std::string, double> positions =
          aar_description::BoomJointPositions(*row.boom);
      for (const auto& c : boom_limits) {
        if (c.joint == nullptr || c.joint->WithinLimits(positions.at(c.name))) continue;
        std::ostringstream msg;
        msg << where << "column " << column.at(c.name) + 1 << " '" << c.name
            << "': " << cells[column.at(c.name)] << c.unit << " is outside the limits of joint '"
            << c.name << "', " << c.joint->lower * c.scale << " to " << c.joint->upper * c.scale
            << c.unit;
        throw LoadError(path, msg.str());
      }
    }
    rows.push_back(row);
    try {
      CheckIncreasing(rows, rows.size() - 1);
    } catch (const std::invalid_argument& e) {
      throw LoadError(path, where + e.what());
    }
  }
  if (rows.empty()) throw LoadError(path, "header but no data rows");
  return FlightPath(std::move(rows));
}

FlightPathRow FlightPath::At(double t) const {
  if (!(t > rows_.front().t)) return rows_.front();  // also NaN
  if (t >= rows_.back().t) return rows_.back();
  const auto next = std::upper_bound(rows_.begin(), rows_.end(), t,
                                     [](double v, const FlightPathRow& r) { return v < r.t; });
  const FlightPathRow& b = *next;
  const FlightPathRow& a = *(next - 1);
  const double s = (t - a.t) / (b.t - a.t);
  FlightPathRow out;
  out.t = t;
  out.position_m = (1.0 - s) * a.position_m + s * b.position_m;
  const Eigen::Quaterniond qa(aar_geometry::RotationFromRollPitchYaw(a.rpy));
  const Eigen::Quaterniond qb(aar_geometry::RotationFromRollPitchYaw(b.rpy));
  out.rpy = aar_geometry::RollPitchYawFromRotation(qa.slerp(s, qb).toRotationMatrix());
  if (a.boom) {
    out.boom = BoomPose{(1.0 - s) * a.boom->pitch + s * b.boom->pitch,
                        (1.0 - s) * a.boom->roll + s * b.boom->roll,
                        (1.0 - s) * a.boom->extension + s * b.boom->extension};
  }
  return out;
}

void WriteFlightPath(const std::string& path, const std::vector<FlightPathRow>& rows) {
  std::ofstream out(path);
  if (!out) throw LoadError(path, "cannot be written");
  const bool boom = !rows.empty() && rows.front().boom.has_value();
  out << "t,x,y,z,roll,pitch,yaw" << (boom ? ",boom_pitch,boom_roll,boom_extension" : "") << "\n";
  out << std::fixed;
  // "+ 0.0" turns -0.0 into 0.0 so that files do not print "-0.0000".
  for (const auto& r : rows) {
    out << std::setprecision(3) << r.t << std::setprecision(4);
    for (double v : {r.position_m.x(), r.position_m.y(), r.position_m.z(), RadToDeg(r.rpy.roll),
                     RadToDeg(r.rpy.pitch), RadToDeg(r.rpy.yaw)}) {
      out << ',' << v + 0.0;
    }
    if (boom) {
      for (double v : {RadToDeg(r.boom->pitch), RadToDeg(r.boom->roll), r.boom->extension}) {
        out << ',' << v + 0.0;
      }
    }
    out << "\n";
  }
  if (!out) throw LoadError(path, "write failed");
}

}  // namespace aar_sim
