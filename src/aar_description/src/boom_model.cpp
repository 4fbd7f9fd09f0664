#include "aar_description/boom_model.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include <aar_geometry/pose.h>

#include "aar_description/loft.h"

namespace aar_description {
namespace {

using aar_geometry::DegToRad;
using aar_geometry::TriangleMesh;

constexpr double kTubeEnd = 8.5;              // [m] aft end of the fixed tube from the pivot
constexpr double kTelescopeStart = 7.0;       // [m] telescope link origin from the pivot, retracted
constexpr double kNozzleTip = 3.85;           // [m] nozzle tip from the telescope link origin
constexpr double kRuddevatorX = 6.6;          // [m] ruddevator hinge station from the pivot
constexpr double kRuddevatorDihedral = 35.0;  // [deg] the V

// Collision primitives, each a closed convex part: name, link, shape, size, origin.
struct Part {
  const char* name;
  const char* link;
  const char* geometry;  // URDF geometry element
  double x, y, z, roll, pitch, yaw;
};

std::string Fmt(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

std::string Prefixed(std::string geometry, const std::string& prefix) {
  const std::string key = "{prefix}";
  const size_t at = geometry.find(key);
  if (at != std::string::npos) geometry.replace(at, key.size(), prefix);
  return geometry;
}

std::vector<Part> CollisionParts() {
  const double half_pi = M_PI / 2.0;

  return {
      {"pivot_fairing", "boom", "<box size=\"1.2 0.9 0.6\"/>", -0.4, 0.0, 0.15, 0, 0, 0},
      {"tube_forward", "boom", "<cylinder radius=\"0.30\" length=\"2.5\"/>", -1.25, 0, 0, 0,
       half_pi, 0},
      {"tube_middle", "boom", "<cylinder radius=\"0.27\" length=\"3.0\"/>", -4.0, 0, 0, 0, half_pi,
       0},
      {"tube_aft", "boom", "<cylinder radius=\"0.25\" length=\"3.0\"/>", -7.0, 0, 0, 0, half_pi, 0},
      {"boom_pod", "boom", "<box size=\"0.8 0.3 0.2\"/>", -2.2, 0, -0.38, 0, 0, 0},
      {"ruddevator_collar", "boom", "<cylinder radius=\"0.33\" length=\"0.8\"/>", -kRuddevatorX, 0,
       0, 0, half_pi, 0},
      // Tapered hulls around the visual ruddevators (MakeRuddevatorCollisionMesh); the right
      // one mirrored. A box would stand well clear of the taper and hide receiver it does not.
      {"left_ruddevator", "boom", "<mesh filename=\"{prefix}ruddevator_collision.obj\"/>", 0, 0, 0,
       0, 0, 0},
      {"right_ruddevator", "boom",
       "<mesh filename=\"{prefix}ruddevator_collision.obj\" scale=\"1 -1 1\"/>", 0, 0, 0, 0, 0, 0},
      {"telescope_tube", "telescope", "<cylinder radius=\"0.17\" length=\"3.0\"/>", -1.5, 0, 0, 0,
       half_pi, 0},
      {"nozzle_collar", "telescope", "<cylinder radius=\"0.22\" length=\"0.3\"/>", -3.15, 0, 0, 0,
       half_pi, 0},
      {"nozzle", "telescope", "<cylinder radius=\"0.12\" length=\"0.45\"/>", -3.525, 0, 0, 0,
       half_pi, 0},
      {"nozzle_ball", "telescope", "<sphere radius=\"0.11\"/>", -3.75, 0, 0, 0, 0, 0},
  };
}

// A tube along -x from x0 to x1 with radius r0 -> r1, in `mesh` as `part`.
void AppendTube(TriangleMesh& mesh, const std::string& part, double x0, double x1, double r0,
                double r1, int segments, bool caps) {
  std::vector<Ring> rings = {SuperellipseRing(x0, 0, 0, r0, r0, 2.0, segments),
                             SuperellipseRing(x1, 0, 0, r1, r1, 2.0, segments)};
  AppendLoft(mesh, part, rings, caps, caps);
}

// A straight loft of NACA 0010 sections from the root (0.25 m out along the V, chord 1.3 m) to
// the tip (2.25 m, chord 0.8 m), through `stations` + 1 sections. `blunt` > 0 thickens each
// section by blunt x chord-position on either side, which keeps it convex and holds the plain
// section, and ends it in a flat trailing edge (blunt x chord thick on either side): a sharp edge
// would make the grown collision part spike far past the margin.
void AppendRuddevator(TriangleMesh& mesh, const std::string& part, double side, int stations = 4,
                      double blunt = 0.0) {
  const double v = DegToRad(kRuddevatorDihedral);
  const Eigen::Vector3d out(0.0, side * std::cos(v), std::sin(v));
  const Eigen::Vector3d thickness = Eigen::Vector3d::UnitX().cross(out).normalized();
  constexpr int kPoints = 12;  // per surface: kPoints + 1 upper (TE to LE), then the lower ones
  std::vector<Ring> rings;
  for (int i = 0; i <= stations; ++i) {
    const double eta = static_cast<double>(i) / stations;
    const double chord = 1.3 - 0.5 * eta;
    const Eigen::Vector3d le(-kRuddevatorX + 0.45 - 0.3 * eta, 0, 0);
    std::vector<Eigen::Vector2d> section = AirfoilSection(chord, 0.10, kPoints);
    if (blunt > 0.0) {
      for (size_t k = 0; k < section.size(); ++k)
        section[k].y() += (k <= kPoints ? 1.0 : -1.0) * blunt * section[k].x();
      section.emplace_back(chord, -section.front().y());  // the lower trailing-edge corner
    }
    Ring ring;
    for (const auto& uv : section) {
      ring.push_back(le + (0.25 + 2.0 * eta) * out + Eigen::Vector3d(-uv.x(), 0, 0) +
                     uv.y() * thickness);
    }
    rings.push_back(ring);
  }
  AppendLoft(mesh, part, rings, true, true);
}

}  // namespace

TriangleMesh MakeRuddevatorCollisionMesh() {
  // Root and tip sections are similar and parallel, so the loft between just those two is
  // their convex hull (each side quad joins parallel edges). Thickened by 1 % of the chord at
  // the trailing edge, it holds the visual surface and has no knife edge.
  TriangleMesh mesh;
  AppendRuddevator(mesh, "left_ruddevator", 1.0, 1, 0.01);
  return mesh;
}

BoomPose DefaultBoomPose() { return BoomPose{DegToRad(30.0), 0.0, 0.5}; }

std::map<std::string, double> BoomJointPositions(const BoomPose& pose) {
  return {{"boom_pitch", pose.pitch}, {"boom_roll", pose.roll}, {"boom_extension", pose.extension}};
}

std::string MakeBoomUrdf(const BoomModelOptions& options, const std::string& prefix) {
  std::ostringstream u;
  const Eigen::Vector3d& p = options.pivot_in_tanker;
  u << "<?xml version=\"1.0\"?>\n"
    << "<!-- Generated by aar_description/generate_models: KC-10 class refueling boom. "
       "Collision "
       "geometry:\n"
    << "     closed convex parts (input of shadow volumes); visual: detailed meshes. -->\n"
    << "<robot name=\"kc10_boom\">\n"
    << "  <link name=\"tanker\"/>\n"
    << "  <joint name=\"boom_mount\" type=\"fixed\">\n"
    << "    <parent link=\"tanker\"/><child link=\"boom_pivot\"/>\n"
    << "    <origin xyz=\"" << Fmt(p.x()) << " " << Fmt(p.y()) << " " << Fmt(p.z())
    << "\" rpy=\"0 0 0\"/>\n"
    << "  </joint>\n"
    << "  <link name=\"boom_pivot\"/>\n"
    << "  <joint name=\"boom_roll\" type=\"revolute\">\n"
    << "    <parent link=\"boom_pivot\"/><child link=\"boom_gimbal\"/>\n"
    << "    <axis xyz=\"1 0 0\"/>\n"
    << "    <limit lower=\"" << Fmt(DegToRad(-15)) << "\" upper=\"" << Fmt(DegToRad(15))
    << "\" effort=\"0\" velocity=\"0.5\"/>\n"
    << "  </joint>\n"
    << "  <link name=\"boom_gimbal\"/>\n"
    << "  <joint name=\"boom_pitch\" type=\"revolute\">\n"
    << "    <parent link=\"boom_gimbal\"/><child link=\"boom\"/>\n"
    << "    <axis xyz=\"0 -1 0\"/>\n"
    << "    <limit lower=\"" << Fmt(DegToRad(20)) << "\" upper=\"" << Fmt(DegToRad(40))
    << "\" effort=\"0\" velocity=\"0.5\"/>\n"
    << "  </joint>\n";
  auto link = [&](const std::string& name, const std::string& mesh) {
    u << "  <link name=\"" << name << "\">\n"
      << "    <visual name=\"" << name << "_visual\">\n"
      << "      <geometry><mesh filename=\"" << prefix << mesh << "\"/></geometry>\n"
      << "    </visual>\n";
    for (const Part& part : CollisionParts()) {
      if (name != part.link) continue;
      u << "    <collision name=\"" << part.name << "\">\n"
        << "      <origin xyz=\"" << Fmt(part.x) << " " << Fmt(part.y) << " " << Fmt(part.z)
        << "\" rpy=\"" << Fmt(part.roll) << " " << Fmt(part.pitch) << " " << Fmt(part.yaw)
        << "\"/>\n"
        << "      <geometry>" << Prefixed(part.geometry, prefix) << "</geometry>\n"
        << "    </collision>\n";
    }
    u << "  </link>\n";
  };
  link("boom", "boom_visual.obj");
  u << "  <joint name=\"boom_extension\" type=\"prismatic\">\n"
    << "    <parent link=\"boom\"/><child link=\"telescope\"/>\n"
    << "    <origin xyz=\"" << Fmt(-kTelescopeStart) << " 0 0\" rpy=\"0 0 0\"/>\n"
    << "    <axis xyz=\"-1 0 0\"/>\n"
    << "    <limit lower=\"0\" upper=\"6\" effort=\"0\" velocity=\"0.5\"/>\n"
    << "  </joint>\n";
  link("telescope", "telescope_visual.obj");
  u << "  <joint name=\"nozzle_tip_mount\" type=\"fixed\">\n"
    << "    <parent link=\"telescope\"/><child link=\"nozzle_tip\"/>\n"
    << "    <origin xyz=\"" << Fmt(-kNozzleTip) << " 0 0\" rpy=\"0 0 0\"/>\n"
    << "  </joint>\n"
    << "  <link name=\"nozzle_tip\"/>\n"
    << "</robot>\n";
  return u.str();
}

TriangleMesh MakeBoomVisualMesh(const std::string& link, const BoomModelOptions& options) {
  TriangleMesh mesh;
  const int n = options.segments;
  if (link == "boom") {
    // Pivot fairing: a rounded box hugging the pivot.
    std::vector<Ring> fairing;
    for (double x : {0.2, -0.1, -0.7, -1.0}) {
      const double s = (x > -0.05 && x < 0.1) || x < -0.8 ? 0.8 : 1.0;
      fairing.push_back(SuperellipseRing(x, 0, 0.15, 0.45 * s, 0.30 * s, 4.0, n));
    }
    AppendLoft(mesh, "pivot_fairing", fairing, true, true);
    AppendTube(mesh, "tube_forward", -0.1, -2.5, 0.29, 0.28, n, true);
    AppendTube(mesh, "tube_middle", -2.5, -5.5, 0.27, 0.26, n, true);
    AppendTube(mesh, "tube_aft", -5.5, -kTubeEnd, 0.245, 0.24, n, true);
    AppendTube(mesh, "ruddevator_collar", -kRuddevatorX + 0.4, -kRuddevatorX - 0.4, 0.32, 0.30, n,
               true);
    std::vector<Ring> pod = {SuperellipseRing(-1.85, 0, -0.36, 0.10, 0.07, 2.0, n),
                             SuperellipseRing(-2.1, 0, -0.38, 0.14, 0.09, 2.0, n),
                             SuperellipseRing(-2.55, 0, -0.38, 0.14, 0.09, 2.0, n)};
    AppendLoft(mesh, "boom_pod", pod, true, true);
    AppendRuddevator(mesh, "left_ruddevator", 1.0);
    AppendRuddevator(mesh, "right_ruddevator", -1.0);
  } else if (link == "telescope") {
    AppendTube(mesh, "telescope_tube", 0.0, -3.0, 0.165, 0.165, n, true);
    AppendTube(mesh, "nozzle_collar", -3.0, -3.3, 0.21, 0.19, n, true);
    AppendTube(mesh, "nozzle", -3.3, -3.7, 0.12, 0.10, n, true);
    std::vector<Ring> ball;
    for (int i = 0; i <= 6; ++i) {
      const double a = M_PI * i / 6.0;
      ball.push_back(SuperellipseRing(-3.75 + 0.10 * std::cos(a), 0, 0,
                                      std::max(0.01, 0.10 * std::sin(a)),
                                      std::max(0.01, 0.10 * std::sin(a)), 2.0, n));
    }
    AppendLoft(mesh, "nozzle_ball", ball, true, true);
  } else {
    throw std::invalid_argument("boom link '" + link + "' has no visual mesh");
  }
  return mesh;
}

}  // namespace aar_description
