#include "aar_description/receiver_model.h"

#include <cmath>

#include <aar_geometry/pose.h>

#include "aar_description/loft.h"

namespace aar_description {
namespace {

using aar_geometry::DegToRad;
using aar_geometry::TriangleMesh;

// Fuselage stations: x [m], half-width [m], half-height [m], centre height z [m], squareness.
struct Station {
  double x, half_width, half_height, z, exponent;
};

// Nose (from the tip back to the cabin) and fuselage (cabin to tail cone) share the cabin ring.
const Station kNose[] = {{6.00, 0.04, 0.04, -0.10, 2.0}, {5.80, 0.28, 0.26, -0.10, 2.0},
                         {5.40, 0.50, 0.46, -0.06, 2.2}, {4.80, 0.68, 0.66, 0.00, 2.4},
                         {4.10, 0.79, 0.82, 0.04, 2.5},  {3.60, 0.82, 0.86, 0.05, 2.6}};
const Station kFuselage[] = {{3.60, 0.82, 0.86, 0.05, 2.6},  {1.50, 0.825, 0.88, 0.05, 2.6},
                             {-1.50, 0.82, 0.87, 0.06, 2.6}, {-3.00, 0.74, 0.78, 0.12, 2.5},
                             {-4.50, 0.56, 0.60, 0.28, 2.3}, {-6.00, 0.34, 0.38, 0.48, 2.1},
                             {-7.00, 0.16, 0.20, 0.62, 2.0}, {-7.36, 0.03, 0.04, 0.68, 2.0}};

// Wing: root chord line at z = -0.45 m, root section inside the fuselage, 6 deg dihedral.
constexpr double kWingRootY = 0.55;   // [m]
constexpr double kWingRootZ = -0.45;  // [m]
constexpr double kNacelleY = 2.60;    // [m] either side of the centreline

double WingZ(double y) { return kWingRootZ + (std::abs(y) - kWingRootY) * std::tan(DegToRad(6.0)); }

Ring StationRing(const Station& s, int segments) {
  return SuperellipseRing(s.x, 0.0, s.z, s.half_width, s.half_height, s.exponent, segments);
}

// A lifting surface lofted through airfoil sections. `place(eta)` gives the leading-edge point
// of the section at span fraction eta in [0, 1], `chord(eta)` its chord; the section lies in the
// plane spanned by -x (chord) and `thickness_axis`.
template <typename Place, typename Chord>
void AppendSurface(TriangleMesh& mesh, const std::string& part, int sections, int chord_points,
                   double thickness_ratio, const Eigen::Vector3d& thickness_axis, Place place,
                   Chord chord, bool cap_root) {
  std::vector<Ring> rings;
  for (int i = 0; i <= sections; ++i) {
    const double eta = static_cast<double>(i) / sections;
    const Eigen::Vector3d le = place(eta);
    Ring ring;
    for (const auto& uv : AirfoilSection(chord(eta), thickness_ratio, chord_points)) {
      ring.push_back(le + Eigen::Vector3d(-uv.x(), 0.0, 0.0) + uv.y() * thickness_axis);
    }
    rings.push_back(ring);
  }
  AppendLoft(mesh, part, rings, cap_root, true);
}

void AppendWing(TriangleMesh& mesh, const std::string& part, double side,
                const ReceiverModelOptions& o) {
  const double tip_y = 16.61 / 2.0;
  const double root_chord = 2.30, tip_chord = 1.00;
  const double root_le_x = 0.25 * root_chord;  // root quarter chord at the datum, x = 0
  auto place = [&](double eta) {
    const double y = kWingRootY + eta * (tip_y - kWingRootY);
    const double le_x = root_le_x - eta * 0.35;  // slight leading-edge sweep
    return Eigen::Vector3d(le_x, side * y, WingZ(y));
  };
  auto chord = [&](double eta) { return root_chord + eta * (tip_chord - root_chord); };
  AppendSurface(mesh, part, o.span_sections, o.chord_points, 0.15, Eigen::Vector3d::UnitZ(), place,
                chord, false);
}

void AppendNacelle(TriangleMesh& mesh, const std::string& part, double side, int segments) {
  const double y = side * kNacelleY;
  const double z = WingZ(kNacelleY) + 0.05;
  // x, radius: spinner, intake, body, aft fairing over the wing.
  const double profile[][2] = {{3.40, 0.03}, {3.30, 0.16}, {3.05, 0.30},  {2.70, 0.40},
                               {1.60, 0.42}, {0.20, 0.40}, {-0.90, 0.26}, {-1.50, 0.05}};
  std::vector<Ring> rings;
  for (const auto& p : profile)
    rings.push_back(SuperellipseRing(p[0], y, z, p[1], p[1] * 1.1, 2.0, segments));
  AppendLoft(mesh, part, rings, true, true);
}

void AppendPropeller(TriangleMesh& mesh, const std::string& part, double side) {
  const double y = side * kNacelleY;
  const double z = WingZ(kNacelleY) + 0.05;
  const double radius = 1.25, width = 0.18, thickness = 0.04;
  for (int blade = 0; blade < 4; ++blade) {
    const double a = DegToRad(45.0 + 90.0 * blade);
    const Eigen::Vector3d dir(0.0, std::cos(a), std::sin(a));
    const Eigen::Vector3d across = Eigen::Vector3d::UnitX().cross(dir);
    std::vector<Ring> rings;
    for (double r : {0.15, radius}) {
      const Eigen::Vector3d c(3.36, y + r * dir.y(), z + r * dir.z());
      rings.push_back({c + 0.5 * width * across + Eigen::Vector3d(thickness, 0, 0),
                       c - 0.5 * width * across + Eigen::Vector3d(thickness, 0, 0),
                       c - 0.5 * width * across, c + 0.5 * width * across});
    }
    AppendLoft(mesh, part, rings, true, true);
  }
}

// RQ-4 class UAV, in fuselage stations: s [m] aft of the nose tip.
constexpr double kUavDatumStation = 4.6;  // body origin [m aft of the nose tip]
double UavX(double station) { return kUavDatumStation - station; }

// Station, half-width, half-height, centre height z, squareness (x as a station).
const Station kUavNose[] = {{0.00, 0.04, 0.04, -0.05, 2.0},
                            {0.30, 0.40, 0.38, 0.00, 2.0},
                            {0.90, 0.66, 0.66, 0.08, 2.2},
                            {1.80, 0.78, 0.80, 0.12, 2.4}};
const Station kUavFuselage[] = {{1.80, 0.78, 0.80, 0.12, 2.4},  {3.00, 0.76, 0.78, 0.10, 2.5},
                                {4.50, 0.68, 0.66, 0.04, 2.5},  {6.00, 0.62, 0.56, 0.00, 2.5},
                                {8.00, 0.52, 0.46, 0.00, 2.4},  {10.00, 0.40, 0.36, 0.05, 2.2},
                                {12.00, 0.28, 0.26, 0.12, 2.0}, {13.40, 0.20, 0.20, 0.18, 2.0}};

Ring UavRing(const Station& s, int segments) {
  return SuperellipseRing(UavX(s.x), 0.0, s.z, s.half_width, s.half_height, s.exponent, segments);
}

}  // namespace

Eigen::Isometry3d UavStationToBody() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();  // yaw 180 deg
  T.translation() = Eigen::Vector3d(kUavDatumStation, 0.0, 0.0);
  return T;
}

Eigen::Vector3d UavReceptacleInReceiver() { return {0.4, 0.0, 0.74}; }

TriangleMesh MakeUavMesh(const UavModelOptions& o) {
  TriangleMesh mesh;
  std::vector<Ring> rings;
  for (const auto& s : kUavNose) rings.push_back(UavRing(s, o.ring_segments));
  AppendLoft(mesh, "nose", rings, true, false);
  rings.clear();
  for (const auto& s : kUavFuselage) rings.push_back(UavRing(s, o.ring_segments));
  AppendLoft(mesh, "fuselage", rings, false, true);

  // Shoulder wing: root section inside the fuselage at y = 0.3 m, chord line 0.2 m above the
  // reference line, leading edge from station 5.0 (root) to 5.6 (tip), 3 deg dihedral.
  for (const double side : {1.0, -1.0}) {
    const double root_y = 0.30, tip_y = 39.9 / 2.0;
    AppendSurface(
        mesh, side > 0 ? "left_wing" : "right_wing", o.span_sections, o.chord_points, 0.14,
        Eigen::Vector3d::UnitZ(),
        [&](double eta) {
          const double y = root_y + eta * (tip_y - root_y);
          return Eigen::Vector3d(UavX(5.0 + 0.6 * eta), side * y,
                                 0.20 + (y - root_y) * std::tan(DegToRad(3.0)));
        },
        [](double eta) { return 2.20 - eta * 1.45; }, false);
  }

  // Engine nacelle on top of the aft fuselage, intake above the wing's trailing edge.
  const double profile[][2] = {{7.00, 0.30},  {7.20, 0.42},  {8.00, 0.50}, {10.00, 0.48},
                               {11.50, 0.38}, {12.40, 0.26}, {12.70, 0.10}};
  rings.clear();
  for (const auto& p : profile)
    rings.push_back(SuperellipseRing(UavX(p[0]), 0.0, 0.80, p[1], p[1], 2.0, o.ring_segments));
  AppendLoft(mesh, "engine_nacelle", rings, true, true);

  // V-tail: two 3 m surfaces at 50 deg from the horizontal, roots inside the tail cone, chord
  // 1.9 m at the root and 0.9 m at the tip, the tip's trailing edge at station 14.5 (length).
  const double dihedral = DegToRad(50.0);
  for (const double side : {1.0, -1.0}) {
    const Eigen::Vector3d along(0.0, side * std::cos(dihedral), std::sin(dihedral));
    const Eigen::Vector3d thickness(0.0, -side * std::sin(dihedral), std::cos(dihedral));
    AppendSurface(
        mesh, side > 0 ? "left_tail" : "right_tail", 6, o.chord_points, 0.10, thickness,
        [&](double eta) -> Eigen::Vector3d {  // not an Eigen expression of a temporary
          return Eigen::Vector3d(UavX(11.4 + 2.2 * eta), side * 0.05, 0.12) + 3.0 * eta * along;
        },
        [](double eta) { return 1.90 - eta * 1.0; }, false);
  }
  return mesh;
}

Eigen::Vector3d ReceptacleInReceiver() { return {-0.3, 0.0, 0.93}; }

TriangleMesh MakeReceiverMesh(const ReceiverModelOptions& o) {
  TriangleMesh mesh;
  std::vector<Ring> rings;
  for (const auto& s : kNose) rings.push_back(StationRing(s, o.ring_segments));
  AppendLoft(mesh, "nose", rings, true, false);
  rings.clear();
  for (const auto& s : kFuselage) rings.push_back(StationRing(s, o.ring_segments));
  AppendLoft(mesh, "fuselage", rings, false, true);

  AppendWing(mesh, "left_wing", 1.0, o);
  AppendWing(mesh, "right_wing", -1.0, o);
  AppendNacelle(mesh, "left_nacelle", 1.0, o.ring_segments);
  AppendNacelle(mesh, "right_nacelle", -1.0, o.ring_segments);

  // Vertical tail: root on the tail cone, tip 2.2 m higher carrying the horizontal tail.
  AppendSurface(
      mesh, "vertical_tail", 6, o.chord_points, 0.12, Eigen::Vector3d::UnitY(),
      [](double eta) { return Eigen::Vector3d(-4.40 - eta * 1.55, 0.0, 0.55 + eta * 2.35); },
      [](double eta) { return 2.70 - eta * 1.25; }, false);
  // T-tail horizontal surface: 5.6 m span, both halves lofted tip to tip through the fin top.
  AppendSurface(
      mesh, "horizontal_tail", 12, o.chord_points, 0.10, Eigen::Vector3d::UnitZ(),
      [](double eta) {
        const double y = -2.8 + 5.6 * eta;
        return Eigen::Vector3d(-5.90 - 0.35 * std::abs(y) / 2.8, y, 2.92);
      },
      [](double eta) { return 1.35 - 0.55 * std::abs(2.0 * eta - 1.0); }, true);
  // Ventral fin under the tail cone.
  AppendSurface(
      mesh, "ventral_fin", 3, o.chord_points, 0.10, Eigen::Vector3d::UnitY(),
      [](double eta) { return Eigen::Vector3d(-5.30 - eta * 0.6, 0.0, 0.05 - eta * 0.45); },
      [](double eta) { return 1.40 - eta * 0.6; }, false);

  if (o.propellers) {
    AppendPropeller(mesh, "left_propeller", 1.0);
    AppendPropeller(mesh, "right_propeller", -1.0);
  }
  return mesh;
}

Eigen::Vector3d PropellerHubInReceiver(double side) {
  return {3.30, side * kNacelleY, WingZ(kNacelleY) + 0.05};
}

}  // namespace aar_description
