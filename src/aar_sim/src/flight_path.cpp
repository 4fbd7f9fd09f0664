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

// FlightPath::Load's steps.

// A CSV file's lines, blank lines and '#' comments skipped, with their line numbers.
class CsvLines {
 public:
  explicit CsvLines(const std::string& path) : in_(path) {}
  bool Next(std::string* line) {
    while (std::getline(in_, *line)) {
      ++line_number_;
      if (line->find_first_not_of(" \t\r") == std::string::npos || (*line)[0] == '#') continue;
      return true;
    }
    return false;
  }
  std::string Where() const { return "line " + std::to_string(line_number_) + ": "; }

 private:
  std::ifstream in_;
  int line_number_ = 0;
};

struct CsvHeader {
  std::vector<std::string> names;
  std::map<std::string, size_t> column;  // by name
  bool boom = false;                     // with the three boom columns
  std::string where;                     // "line N: "
};

// The header line: every required column, each column once, the boom columns all or none.
CsvHeader ReadHeader(const std::string& path, CsvLines* csv) {
  CsvHeader header;
  std::string line;
  while (header.names.empty() && csv->Next(&line)) header.names = SplitCsv(line);
  if (header.names.empty()) {
    throw LoadError(path, "no header line (expected t,x,y,z,roll,pitch,yaw)");
  }
  header.where = csv->Where();
  for (size_t c = 0; c < header.names.size(); ++c) {
    if (!header.column.emplace(header.names[c], c).second) {
      throw LoadError(path, header.where + "column '" + header.names[c] + "' appears twice");
    }
  }
  for (const auto& name : kRequired) {
    if (!header.column.count(name)) {
      throw LoadError(path, header.where + "missing column '" + name + "'");
    }
  }
  const int boom_columns =
      static_cast<int>(std::count_if(kBoom.begin(), kBoom.end(), [&](const std::string& n) {
        return header.column.count(n) > 0;
      }));
  if (boom_columns != 0 && boom_columns != 3) {
    throw LoadError(path, header.where +
                              "boom columns must be all of boom_pitch, boom_roll, "
                              "boom_extension or none");
  }
  header.boom = boom_columns == 3;
  return header;
}

// Boom columns: CSV name, joint, CSV unit per joint unit (deg per rad or m per m), unit name.
struct BoomColumn {
  std::string name;
  const aar_geometry::Joint* joint;
  double scale;
  const char* unit;
};

std::vector<BoomColumn> BoomLimits(const std::string& path, const CsvHeader& header,
                                   const FlightPathOptions& options) {
  std::vector<BoomColumn> boom_limits;
  if (!header.boom) return boom_limits;
  for (const auto& name : kBoom) {
    const bool angle = name != "boom_extension";
    boom_limits.push_back({name, BoomJoint(path, header.where, options, name),
                           angle ? RadToDeg(1.0) : 1.0, angle ? " deg" : " m"});
  }
  return boom_limits;
}

// One data row's cells, for messages naming the file, line and column.
struct RowCells {
  const std::string& path;
  const std::string& where;  // "line N: "
  const CsvHeader& header;
  const std::vector<std::string>& cells;

  const std::string& Cell(const std::string& name) const { return cells[header.column.at(name)]; }
  double Number(const std::string& name) const {
    const std::string& cell = Cell(name);
    char* end = nullptr;
    const double value = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(value)) {
      throw LoadError(path, where + "column '" + name + "': '" + cell + "' is not a finite number");
    }
    return value;
  }
};

FlightPathRow ParseRow(const RowCells& r) {
  FlightPathRow row;
  row.t = r.Number("t");
  row.position_m = {r.Number("x"), r.Number("y"), r.Number("z")};
  row.rpy = {DegToRad(r.Number("roll")), DegToRad(r.Number("pitch")), DegToRad(r.Number("yaw"))};
  if (r.header.boom) {
    row.boom = BoomPose{DegToRad(r.Number("boom_pitch")), DegToRad(r.Number("boom_roll")),
                        r.Number("boom_extension")};
  }
  return row;
}

// The joint states the sim publishes: outside the URDF's limits no real boom goes there.
void CheckBoomLimits(const RowCells& r, const BoomPose& boom,
                     const std::vector<BoomColumn>& boom_limits) {
  const std::map<std::string, double> positions = aar_description::BoomJointPositions(boom);
  for (const auto& c : boom_limits) {
    if (c.joint == nullptr || c.joint->WithinLimits(positions.at(c.name))) continue;
    std::ostringstream msg;
    msg << r.where << "column " << r.header.column.at(c.name) + 1 << " '" << c.name
        << "': " << r.Cell(c.name) << c.unit << " is outside the limits of joint '" << c.name
        << "', " << c.joint->lower * c.scale << " to " << c.joint->upper * c.scale << c.unit;
    throw LoadError(r.path, msg.str());
  }
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
  CsvLines csv(path);
  const CsvHeader header = ReadHeader(path, &csv);
  const std::vector<BoomColumn> boom_limits = BoomLimits(path, header, options);
  std::vector<FlightPathRow> rows;
  std::string line;
  while (csv.Next(&line)) {
    const std::string where = csv.Where();
    const std::vector<std::string> cells = SplitCsv(line);
    if (cells.size() != header.names.size()) {
      throw LoadError(path, where + std::to_string(cells.size()) + " cells, header has " +
                                std::to_string(header.names.size()));
    }
    const RowCells row_cells{path, where, header, cells};
    const FlightPathRow row = ParseRow(row_cells);
    if (row.boom) CheckBoomLimits(row_cells, *row.boom, boom_limits);
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
