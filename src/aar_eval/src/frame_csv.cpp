// Frame CSVs (tables.h: FrameCsvHeader, FrameCsvRow, WriteFrameCsv, ReadFrameCsv), their columns
// described once: name, how a frame writes the cell, how a cell reads into a frame.
#include "aar_eval/tables.h"

#include <array>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <aar_geometry/load_error.h>

namespace aar_eval {
namespace {

double Nan() { return std::numeric_limits<double>::quiet_NaN(); }

// The cells of a line of a frame CSV.
struct CsvLine {
  const std::string& path;
  int number = 0;
  std::vector<std::string> cells;

  [[noreturn]] void Fail(const std::string& what) const {
    throw aar_geometry::LoadError(path, "line " + std::to_string(number) + ": " + what);
  }

  // The whole of cell i as a number.
  double Number(size_t i) const {
    try {
      size_t used = 0;
      const double v = std::stod(cells[i], &used);
      if (used != cells[i].size()) throw std::invalid_argument("");
      return v;
    } catch (const std::exception&) {
      Fail("'" + cells[i] + "' is not a number");
    }
  }
};

struct FrameColumn {
  std::string name;
  std::function<void(std::ostream&, const FrameRecord&)> write;
  // Reads cell i into the frame, whose earlier columns are read.
  std::function<void(const CsvLine&, size_t i, FrameRecord&)> read;
};

// A 0/1 column of a flag.
FrameColumn FlagColumn(const std::string& name, bool FrameRecord::*flag) {
  return {name, [flag](std::ostream& s, const FrameRecord& f) { s << (f.*flag ? 1 : 0); },
          [flag](const CsvLine& l, size_t i, FrameRecord& f) { f.*flag = l.Number(i) != 0.0; }};
}

// A number column.
FrameColumn NumberColumn(const std::string& name, double FrameRecord::*number) {
  return {name, [number](std::ostream& s, const FrameRecord& f) { s << f.*number; },
          [number](const CsvLine& l, size_t i, FrameRecord& f) { f.*number = l.Number(i); }};
}

// The six columns of an error (x_m ... yaw_deg after `prefix`), NaN in a frame without it.
void AddErrorColumns(std::vector<FrameColumn>& columns, const std::string& prefix,
                     bool FrameRecord::*has, std::array<double, 6> FrameRecord::*error) {
  static const char* const kNames[6] = {"x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg"};
  for (int c = 0; c < 6; ++c) {
    columns.push_back(
        {prefix + kNames[c],
         [=](std::ostream& s, const FrameRecord& f) { s << (f.*has ? (f.*error)[c] : Nan()); },
         [=](const CsvLine& l, size_t i, FrameRecord& f) {
           (f.*error)[c] = f.*has ? l.Number(i) : 0.0;
         }});
  }
}

// A number of an estimate (NaN in a frame without one).
FrameColumn EstimateNumberColumn(const std::string& name, double FrameRecord::*number) {
  return {
      name,
      [number](std::ostream& s, const FrameRecord& f) { s << (f.estimated ? f.*number : Nan()); },
      [number](const CsvLine& l, size_t i, FrameRecord& f) { f.*number = l.Number(i); }};
}

constexpr size_t kColumnsBeforeTracking = 14;    // up to registration_ms
constexpr size_t kColumnsBeforeHold = 16;        // up to nees
constexpr size_t kColumnsBeforeIntegrity = 23;   // up to published_yaw_deg
constexpr size_t kColumnsBeforeVisibility = 28;  // up to alert
constexpr size_t kColumnsBeforeLeast = 30;       // up to visible_px

// The columns in the file's order. Earlier runs wrote only the first kColumnsBeforeTracking,
// kColumnsBeforeHold, kColumnsBeforeIntegrity, kColumnsBeforeVisibility or kColumnsBeforeLeast.
const std::vector<FrameColumn>& FrameColumns() {
  static const std::vector<FrameColumn> columns = [] {
    std::vector<FrameColumn> c = {
        NumberColumn("t", &FrameRecord::t),
        {"range_m", [](std::ostream& s, const FrameRecord& f) { s << f.range_m; },
         [](const CsvLine& l, size_t i, FrameRecord& f) {
           f.range_m = l.Number(i);
           f.region = aar_geometry::RegionOfRange(f.range_m);
         }},
        {"region",
         [](std::ostream& s, const FrameRecord& f) { s << aar_geometry::RegionName(f.region); },
         [](const CsvLine& l, size_t i, FrameRecord& f) {
           if (aar_geometry::RegionName(f.region) != l.cells[i])
             l.Fail("region '" + l.cells[i] + "' does not match range " + l.cells[i - 1]);
         }},
        FlagColumn("estimated", &FrameRecord::estimated)};
    AddErrorColumns(c, "", &FrameRecord::estimated, &FrameRecord::error);
    c.push_back(FlagColumn("converged", &FrameRecord::converged));
    c.push_back({"iterations", [](std::ostream& s, const FrameRecord& f) { s << f.iterations; },
                 [](const CsvLine& l, size_t i, FrameRecord& f) {
                   f.iterations = static_cast<int>(l.Number(i));
                 }});
    c.push_back(NumberColumn("rms_m", &FrameRecord::rms));
    c.push_back(NumberColumn("registration_ms", &FrameRecord::registration_ms));
    // Since tracking (issue 12):
    c.push_back({"track", [](std::ostream& s, const FrameRecord& f) { s << f.track; },
                 [](const CsvLine& l, size_t i, FrameRecord& f) { f.track = l.cells[i]; }});
    c.push_back({"nees",
                 [](std::ostream& s, const FrameRecord& f) { s << (f.estimated ? f.nees : Nan()); },
                 [](const CsvLine& l, size_t i, FrameRecord& f) {
                   f.nees = l.cells[i] == "nan" ? Nan() : l.Number(i);
                 }});
    // Since the miss policy (issue 13):
    c.push_back({"published",
                 [](std::ostream& s, const FrameRecord& f) { s << (f.published ? 1 : 0); },
                 [](const CsvLine& l, size_t i, FrameRecord& f) {
                   f.published = l.Number(i) != 0.0;
                   if (f.estimated && !f.published) l.Fail("estimated but not published");
                 }});
    AddErrorColumns(c, "published_", &FrameRecord::published, &FrameRecord::published_error);
    // Since integrity (issue 42): the estimate's protection levels and alert limits (NaN: none)
    // and its alert.
    c.push_back(EstimateNumberColumn("pl_position_m", &FrameRecord::pl_position_m));
    c.push_back(EstimateNumberColumn("pl_attitude_deg", &FrameRecord::pl_attitude_deg));
    c.push_back(EstimateNumberColumn("al_position_m", &FrameRecord::al_position_m));
    c.push_back(EstimateNumberColumn("al_attitude_deg", &FrameRecord::al_attitude_deg));
    c.push_back(FlagColumn("alert", &FrameRecord::alert));
    // Since visibility (issue 44): what the boom left of the receiver in view (NaN: not measured).
    c.push_back(NumberColumn("visible_fraction", &FrameRecord::visible_fraction));
    c.push_back(NumberColumn("visible_px", &FrameRecord::visible_px));
    c.push_back(NumberColumn("visible_fraction_least", &FrameRecord::visible_fraction_least));
    return c;
  }();
  return columns;
}

// The names of the first n columns, comma-separated.
std::string HeaderOf(size_t n) {
  std::string header;
  for (size_t i = 0; i < n; ++i) header += (i ? "," : "") + FrameColumns()[i].name;
  return header;
}

// How many columns a file with this header line has; 0 when it is no frame CSV header.
size_t ColumnsOfHeader(const std::string& line) {
  for (size_t n : {FrameColumns().size(), kColumnsBeforeTracking, kColumnsBeforeHold,
                   kColumnsBeforeIntegrity, kColumnsBeforeVisibility, kColumnsBeforeLeast})
    if (line == HeaderOf(n)) return n;
  return 0;
}

// Line `number`, one frame of `columns` cells.
FrameRecord ParseFrameLine(const std::string& path, int number, const std::string& line,
                           size_t columns) {
  CsvLine csv{path, number, {}};
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) csv.cells.push_back(cell);
  if (line.back() == ',') csv.cells.push_back("");  // getline drops a trailing empty cell
  if (csv.cells.size() != columns) {
    csv.Fail(std::to_string(csv.cells.size()) + " cells, " + std::to_string(columns) + " expected");
  }
  FrameRecord f;
  for (size_t i = 0; i < columns; ++i) FrameColumns()[i].read(csv, i, f);
  if (columns < kColumnsBeforeIntegrity) {  // no record of held estimates: only the frame's own
    f.published = f.estimated;
    f.published_error = f.error;
  }
  return f;
}

}  // namespace

std::string FrameCsvHeader() { return HeaderOf(FrameColumns().size()); }

std::string FrameCsvRow(const FrameRecord& f) {
  std::ostringstream s;
  s << std::setprecision(17);
  for (size_t i = 0; i < FrameColumns().size(); ++i) {
    if (i) s << ',';
    FrameColumns()[i].write(s, f);
  }
  return s.str();
}

void WriteFrameCsv(const std::string& path, const std::vector<FrameRecord>& frames) {
  std::ofstream out(path);
  if (!out) throw aar_geometry::LoadError(path, "cannot be written");
  out << FrameCsvHeader() << "\n";
  for (const auto& f : frames) out << FrameCsvRow(f) << "\n";
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw aar_geometry::LoadError(path, "write failed");
}

std::vector<FrameRecord> ReadFrameCsv(const std::string& path) {
  aar_geometry::CheckReadableFile(path);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const size_t columns = ColumnsOfHeader(line);
  if (columns == 0) throw aar_geometry::LoadError(path, "line 1: not a frame CSV header");
  std::vector<FrameRecord> frames;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty()) frames.push_back(ParseFrameLine(path, number, line, columns));
  }
  return frames;
}

}  // namespace aar_eval
