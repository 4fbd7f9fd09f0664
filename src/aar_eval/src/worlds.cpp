#include "aar_eval/worlds.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "aar_eval/suite.h"
#include "aar_eval/tables.h"
#include "markdown.h"

namespace aar_eval {
namespace {

double Nan() { return std::numeric_limits<double>::quiet_NaN(); }

// One approach's figures in one region: frames, estimated frames, mean error magnitudes.
struct RegionFigures {
  int frames = 0;
  int estimated = 0;
  double position_m = Nan();    // mean over estimated frames of |(x, y, z) error|
  double attitude_deg = Nan();  // mean over estimated frames of |(roll, pitch, yaw) error|
  double coverage() const { return frames ? 100.0 * estimated / frames : Nan(); }
};

bool InRegion(const FrameRecord& f, const std::string& key) {
  if (f.region == aar_geometry::Region::kOutside) return false;
  return key == "all" || aar_geometry::RegionName(f.region) == key;
}

RegionFigures Figures(const std::vector<FrameRecord>& frames, const std::string& key) {
  RegionFigures r;
  double position = 0.0, attitude = 0.0;
  for (const auto& f : frames) {
    if (!InRegion(f, key)) continue;
    ++r.frames;
    if (!f.estimated) continue;
    ++r.estimated;
    position += std::hypot(f.error[0], f.error[1], f.error[2]);
    attitude += std::hypot(f.error[3], f.error[4], f.error[5]);
  }
  if (r.estimated) {
    r.position_m = position / r.estimated;
    r.attitude_deg = attitude / r.estimated;
  }
  return r;
}

std::vector<std::string> Approaches(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  const fs::path approaches = fs::path(dir) / "approaches";
  if (fs::is_directory(approaches))
    for (const auto& entry : fs::directory_iterator(approaches))
      if (entry.is_directory()) out.push_back(entry.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// records[world][experiment][approach]
using WorldRecords =
    std::map<std::string, std::map<std::string, std::map<std::string, std::vector<FrameRecord>>>>;

// Each world's frames of the reference world's approaches (the reference world's approaches are
// the ground: every other world is compared on them); what the reference world has and another
// lacks into result.missing.
WorldRecords ReadWorlds(const WorldsReportOptions& options, WorldsReportResult& result) {
  namespace fs = std::filesystem;
  const auto& [reference, reference_dir] = options.worlds.front();
  const std::vector<std::string> approaches = Approaches(reference_dir);
  WorldRecords records;
  for (const auto& [world, dir] : options.worlds) {
    for (const auto& e : options.experiments) {
      for (const auto& a : approaches) {
        const fs::path csv = fs::path(dir) / "approaches" / a / e / "frames.csv";
        if (fs::exists(csv)) {
          records[world][e][a] = ReadFrameCsv(csv.string());
        } else if (world != reference &&
                   fs::exists(fs::path(reference_dir) / "approaches" / a / e / "frames.csv")) {
          result.missing.push_back(world + "/" + a + "/" + e);
        }
      }
    }
  }
  if (records[reference].empty())
    throw std::runtime_error("the reference world '" + reference + "' has no results in " +
                             reference_dir + "/approaches");
  return records;
}

// The title, what is missing, each world's run and how to read the tables.
void WriteIntroduction(std::ostream& out, const WorldsReportOptions& options,
                       const WorldsReportResult& result) {
  out << "# The cost of each realism effect\n\n";
  if (!result.missing.empty()) {
    out << "**INCOMPLETE:** missing: ";
    for (size_t i = 0; i < result.missing.size(); ++i) out << (i ? ", " : "") << result.missing[i];
    out << ". Each figure is over the approaches that have results.\n\n";
  }
  out << "## Runs\n\n";
  for (const auto& [world, dir] : options.worlds) {
    out << "**" << world << "** (" << dir << ")\n\n```\n";
    std::ifstream run(dir + "/run.txt");
    if (run && run.peek() != std::ifstream::traits_type::eof())
      out << run.rdbuf();
    else
      out << "(no run.txt)\n";
    out << "```\n\n";
  }
  const int percent = static_cast<int>(std::lround(options.confidence * 100.0));
  out << "Position error: per frame the norm of the x, y, z error along the true body axes [m]; "
         "attitude error: the norm of the roll, pitch, yaw error [deg]; each averaged over the "
         "frames an approach estimated, then over approaches, with the "
      << percent
      << " % Student-t interval in brackets. Cost: per approach the ratio of a world's error to "
         "the "
      << options.worlds.front().first
      << " world's on the same approach, then the mean ratio over approaches (1: no cost).\n";
}

// One world's figures for one experiment in one region, over approaches.
struct WorldRow {
  std::string experiment;
  std::string world;
  bool reference = false;  // the reference world: no cost
  Interval coverage, position, attitude, position_cost, attitude_cost;
};

// The figures of `world` for experiment e in region `key`; the costs against the reference
// world on the same approaches.
WorldRow ComputeWorldRow(const WorldsReportOptions& options, WorldRecords& records,
                         const std::string& e, const std::string& world, const std::string& key) {
  const std::string& reference = options.worlds.front().first;
  std::vector<double> coverage, position, attitude, position_cost, attitude_cost;
  for (const auto& [a, frames] : records[world][e]) {
    const RegionFigures f = Figures(frames, key);
    coverage.push_back(f.coverage());
    position.push_back(f.position_m);
    attitude.push_back(f.attitude_deg);
    const auto ref = records[reference][e].find(a);
    if (world == reference || ref == records[reference][e].end()) continue;
    const RegionFigures r = Figures(ref->second, key);
    position_cost.push_back(r.position_m > 0.0 ? f.position_m / r.position_m : Nan());
    attitude_cost.push_back(r.attitude_deg > 0.0 ? f.attitude_deg / r.attitude_deg : Nan());
  }
  const double confidence = options.confidence;
  WorldRow row;
  row.experiment = e;
  row.world = world;
  row.reference = world == reference;
  row.coverage = MeanInterval(coverage, confidence);
  // A share: the t interval clipped to what can be.
  row.coverage.low = std::max(row.coverage.low, 0.0);
  row.coverage.high = std::min(row.coverage.high, 100.0);
  row.position = MeanInterval(position, confidence);
  row.attitude = MeanInterval(attitude, confidence);
  row.position_cost = MeanInterval(position_cost, confidence);
  row.attitude_cost = MeanInterval(attitude_cost, confidence);
  return row;
}

const Columns<WorldRow>& WorldColumns() {
  // A cost cell: "-" in the reference world's row.
  const auto cost = [](Interval WorldRow::*interval) {
    return [interval](const WorldRow& r) {
      return r.reference ? std::string("-") : FormatInterval(r.*interval, 2);
    };
  };
  static const Columns<WorldRow> columns = {
      {"experiment", Align::kLeft, [](const WorldRow& r) { return r.experiment; }},
      {"world", Align::kLeft, [](const WorldRow& r) { return r.world; }},
      {"approaches", Align::kRight, [](const WorldRow& r) { return std::to_string(r.coverage.n); }},
      {"coverage (%)", Align::kRight,
       [](const WorldRow& r) { return FormatInterval(r.coverage, 1); }},
      {"position (m)", Align::kRight,
       [](const WorldRow& r) { return FormatInterval(r.position, 3); }},
      {"attitude (deg)", Align::kRight,
       [](const WorldRow& r) { return FormatInterval(r.attitude, 3); }},
      {"position cost", Align::kRight, cost(&WorldRow::position_cost)},
      {"attitude cost", Align::kRight, cost(&WorldRow::attitude_cost)}};
  return columns;
}

// Per region, a row per experiment and world.
void WriteRegionTables(std::ostream& out, const WorldsReportOptions& options,
                       WorldRecords& records) {
  const std::string& reference = options.worlds.front().first;
  for (const auto& [key, title] : RegionTitles()) {
    out << "\n## " << title << "\n\n";
    WriteTableHead(out, WorldColumns());
    for (const auto& e : options.experiments) {
      if (!records[reference].count(e)) continue;
      for (const auto& [world, dir] : options.worlds) {
        if (records[world][e].empty()) continue;
        WriteTableRow(out, WorldColumns(), ComputeWorldRow(options, records, e, world, key));
      }
    }
  }
}

}  // namespace

WorldsReportResult WriteWorldsReport(const WorldsReportOptions& options) {
  if (options.worlds.size() < 2)
    throw std::invalid_argument("a worlds report needs the reference world and at least one more");
  if (options.experiments.empty()) throw std::invalid_argument("a worlds report needs experiments");
  WorldsReportResult result;
  result.path = options.path;
  WorldRecords records = ReadWorlds(options, result);

  std::ofstream out(options.path);
  WriteIntroduction(out, options, result);
  WriteRegionTables(out, options, records);
  out.close();  // flushes: a full disk shows here, not in the buffered writes
  if (out.fail()) throw std::runtime_error(options.path + ": write failed");
  return result;
}

}  // namespace aar_eval
