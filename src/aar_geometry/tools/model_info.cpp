// model_info: loads a mesh or URDF the way the pipeline does and reports what later stages rely
// on: parts, triangles, welding, open/non-manifold edges, area, bounds; optionally writes seeded
// surface samples as CSV.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "aar_geometry/adjacency.h"
#include "aar_geometry/load_error.h"
#include "aar_geometry/mesh_io.h"
#include "aar_geometry/robot_model.h"
#include "aar_geometry/surface_sampling.h"
#include "aar_geometry/weld.h"

namespace {

using namespace aar_geometry;

void Usage() {
  std::cerr << "usage: model_info FILE [--collision] [--joint NAME=VALUE]... [--weld EPS]\n"
               "                  [--samples N] [--seed S] [--samples-csv OUT]\n"
               "  FILE        a mesh (OBJ, STL, DAE, PLY, ...) or a robot model (.urdf)\n"
               "  --collision report a URDF's collision geometry (default: visual)\n"
               "  --joint     joint position [rad or m] for a URDF, repeatable\n"
               "  --weld      weld epsilon [m] (default 1e-4, the thesis's)\n"
               "  --samples   surface samples to draw, at least 1 (default: none)\n"
               "  --seed      sampling seed (default 1)\n"
               "  --samples-csv  write samples as x,y,z,nx,ny,nz,part\n";
}

// RFC 4180: quote a field holding a comma, quote or line break; double the quotes.
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// The whole of `text` as a finite number, else invalid_argument naming `what` and the text
// (std::stod takes "1abc" and names only itself on "abc").
double ParseNumber(const std::string& what, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
    throw std::invalid_argument(what + ": '" + text + "' is not a number");
  }
  return value;
}

// The whole of `text` as an integer of at least `min` (std::stoul wraps "-5" round to 2^64 - 5).
uint64_t ParseCount(const std::string& what, const std::string& text, uint64_t min) {
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  errno = 0;
  const uint64_t value = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
  if (!digits || errno == ERANGE || value < min) {
    throw std::invalid_argument(what + ": '" + text + "' is not an integer of at least " +
                                std::to_string(min));
  }
  return value;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void ReportMesh(const TriangleMesh& mesh, double weld_epsilon) {
  const WeldResult welded = WeldVertices(mesh, weld_epsilon);
  const TriangleAdjacency adjacency = BuildAdjacency(welded.mesh);
  const Eigen::AlignedBox3d box = mesh.Bounds();
  std::cout << "triangles: " << mesh.triangles.size() << "\n"
            << "vertices: " << mesh.vertices.size() << " (" << welded.mesh.vertices.size()
            << " after welding within " << weld_epsilon << " m; " << welded.removed_triangles
            << " degenerate triangles removed)\n"
            << std::fixed << std::setprecision(4) << "surface area [m^2]: " << mesh.SurfaceArea()
            << "\n"
            << "bounds min [m]: " << box.min().transpose() << "\n"
            << "bounds max [m]: " << box.max().transpose() << "\n"
            << "open edges: " << adjacency.open_edges.size()
            << ", non-manifold edges: " << adjacency.nonmanifold_edges.size()
            << ", inconsistently wound edges: " << adjacency.inconsistent_edges.size()
            << (adjacency.closed() ? " (closed)"
                                   : " (not closed: " + adjacency.NotClosedReason() + ")")
            << "\n";
  std::cout << "parts: " << mesh.part_names.size() << "\n";
  std::vector<int> counts(mesh.part_names.size(), 0);
  for (int part : mesh.triangle_parts) ++counts[part];
  for (size_t p = 0; p < mesh.part_names.size(); ++p) {
    const TriangleMesh part =
        WeldVertices(SelectParts(mesh, {mesh.part_names[p]}), weld_epsilon).mesh;
    const TriangleAdjacency part_adjacency = BuildAdjacency(part);
    std::cout << "  " << mesh.part_names[p] << ": " << counts[p] << " triangles, "
              << (part_adjacency.closed() ? "closed"
                                          : "not closed (" + part_adjacency.NotClosedReason() + ")")
              << "\n";
  }
}

struct Options {
  std::string file;
  std::string samples_csv;
  bool collision = false;
  double weld_epsilon = 1e-4;
  SurfaceSamplingOptions sampling;
  std::map<std::string, double> joints;
  bool help = false;  // -h or --help: the rest is not read
};

// The command line; invalid_argument saying what is wrong with it.
Options ParseArguments(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      options.help = true;
      return options;
    } else if (arg == "--collision") {
      options.collision = true;
    } else if (arg == "--joint") {
      const std::string kv = value();
      const size_t eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw std::invalid_argument("--joint takes NAME=VALUE, not '" + kv + "'");
      }
      const std::string name = kv.substr(0, eq);
      options.joints[name] = ParseNumber("--joint " + name, kv.substr(eq + 1));
    } else if (arg == "--weld") {
      options.weld_epsilon = ParseNumber("--weld", value());
      if (options.weld_epsilon < 0.0) throw std::invalid_argument("--weld must not be negative");
    } else if (arg == "--samples") {
      options.sampling.num_points = ParseCount("--samples", value(), 1);
    } else if (arg == "--seed") {
      options.sampling.seed = ParseCount("--seed", value(), 0);
    } else if (arg == "--samples-csv") {
      options.samples_csv = value();
    } else if (!arg.empty() && arg[0] == '-') {
      throw std::invalid_argument("unknown option " + arg);
    } else if (options.file.empty()) {
      options.file = arg;
    } else {
      throw std::invalid_argument("more than one FILE given");
    }
  }
  if (options.file.empty()) throw std::invalid_argument("no FILE given");
  if (!options.samples_csv.empty() && options.sampling.num_points == 0) {
    throw std::invalid_argument("--samples-csv needs --samples N");
  }
  return options;
}

// A URDF's links and joints, and its visual or collision geometry at the given joint positions.
TriangleMesh LoadRobotGeometry(const Options& options) {
  const RobotModel model = LoadRobotModel(options.file);
  CheckJointLimits(model, options.joints);
  std::cout << "robot: " << model.name << " (root link " << model.root_link << ", "
            << model.links.size() << " links, " << model.joints.size() << " joints)\n";
  for (const auto& joint : model.joints) {
    std::cout << "  joint " << joint.name << ": " << joint.parent_link << " -> " << joint.child_link
              << (joint.movable() ? ", movable" : ", fixed") << "\n";
  }
  std::cout << (options.collision ? "collision" : "visual") << " geometry:\n";
  TriangleMesh mesh =
      RobotMesh(model, ComputeLinkPoses(model, options.joints),
                options.collision ? GeometryKind::kCollision : GeometryKind::kVisual);
  if (mesh.empty()) throw LoadError(options.file, "the model has no such geometry");
  return mesh;
}

// The mesh of FILE: a URDF's geometry, or a mesh file as LoadMesh reads it.
TriangleMesh LoadGeometry(const Options& options) {
  if (EndsWith(options.file, ".urdf")) return LoadRobotGeometry(options);
  if (!options.joints.empty() || options.collision)
    throw std::invalid_argument("--joint/--collision need a URDF");
  return LoadMesh(options.file);
}

// Samples as x,y,z,nx,ny,nz,part with 6 significant digits.
void WriteSamplesCsv(const std::string& path, const TriangleMesh& mesh,
                     const SurfaceSamples& samples) {
  std::ofstream out(path);
  if (!out) throw LoadError(path, "cannot be written");
  out << "x,y,z,nx,ny,nz,part\n" << std::setprecision(6);
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& p = samples.points[i];
    const auto& n = samples.normals[i];
    out << p.x() << ',' << p.y() << ',' << p.z() << ',' << n.x() << ',' << n.y() << ',' << n.z()
        << ',' << CsvField(mesh.part_names[samples.parts[i]]) << '\n';
  }
}

// Draws the surface samples the options ask for, reports their number and writes them as CSV if
// asked.
void ReportSamples(const TriangleMesh& mesh, const Options& options) {
  const SurfaceSamples samples = SampleSurface(mesh, options.sampling);
  std::cout << "samples: " << samples.size() << " (seed " << options.sampling.seed << ")\n";
  if (options.samples_csv.empty()) return;
  WriteSamplesCsv(options.samples_csv, mesh, samples);
  std::cout << "wrote " << options.samples_csv << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    options = ParseArguments(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "model_info: " << e.what() << "\n";
    Usage();
    return 2;
  }
  if (options.help) {
    Usage();
    return 0;
  }
  try {
    const TriangleMesh mesh = LoadGeometry(options);
    ReportMesh(mesh, options.weld_epsilon);
    if (options.sampling.num_points > 0) ReportSamples(mesh, options);
  } catch (const std::exception& e) {
    std::cerr << "model_info: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
