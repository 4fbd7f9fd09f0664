#pragma once

#include <aar_geometry/triangle_mesh.h>

namespace aar_description {

// Procedural C-12 / King Air 200 class receiver from published dimensions: length 13.36 m,
// span 16.61 m, fuselage 1.65 m wide, wing dihedral 6 deg, T-tail of 5.6 m span, nacelles
// 2.6 m either side of the centreline. Without landing gear it stands about 3.8 m tall (the
// published 4.52 m includes the gear).
//
// Receiver body frame (REP-103): x from tail to nose, y from the right wing to the left, z up.
// Origin (the aircraft datum): on the fuselage centreline at the wing root's quarter chord,
// 0.45 m above the wing root chord line. The nose tip is at x = +6.0 m, the tail cone at -7.36 m.
struct ReceiverModelOptions {
  int ring_segments = 40;   // facets around fuselage and nacelles
  int chord_points = 18;    // points along each airfoil surface
  int span_sections = 14;   // sections along each wing
  bool propellers = false;  // four-blade propellers, stopped (thesis: not modelled)
};

// Parts: nose, fuselage, left_wing, right_wing, left_nacelle, right_nacelle, vertical_tail,
// horizontal_tail, ventral_fin (and left_propeller, right_propeller when enabled). "Wings and
// nose" (thesis Fig. 11) is {nose, left_wing, right_wing}. Welding gives a mesh whose only open
// edges are where parts meet (a wing root inside the fuselage, say).
aar_geometry::TriangleMesh MakeReceiverMesh(const ReceiverModelOptions& options = {});

// Refueling receptacle on the upper fuselage above the wing root (as on UAV-class receivers), in
// the receiver frame [m].
Eigen::Vector3d ReceptacleInReceiver();

// The C-12's propeller hub (the disc's centre, just behind the spinner's tip) on the left
// (side +1) or right (side -1) nacelle, in the receiver frame [m].
Eigen::Vector3d PropellerHubInReceiver(double side);

// Procedural RQ-4B / MQ-4C class high-altitude UAV from published dimensions: span 39.9 m,
// length 14.5 m; a bulged forward fuselage (the satellite-antenna radome, about 1.6 m tall and
// wide), a shoulder wing with 3 deg dihedral (root chord 2.2 m, tip 0.75 m), one engine nacelle
// on top of the aft fuselage and a V-tail of two 3 m surfaces at 50 deg. Other figures are
// estimates from published drawings. No landing gear (the published 4.7 m height includes it).
//
// Built in the receiver body frame (REP-103) with the origin on the fuselage reference line
// 4.6 m aft of the nose tip, 0.4 m aft of the receptacle (so that contact falls in region C, as
// the C-12's does). The file, models/rq4.obj, is written in fuselage-station axes instead (x
// from the nose tip aft, y to the right wing, z up, [m]), as drawings give them;
// models/rq4.yaml maps them into the body frame (kUavStationToBody).
struct UavModelOptions {
  int ring_segments = 40;  // facets around fuselage and nacelle
  int chord_points = 18;   // points along each airfoil surface
  int span_sections = 24;  // sections along each wing
};

// Parts: nose, fuselage, left_wing, right_wing, engine_nacelle, left_tail, right_tail. "Wings
// and nose" is {nose, left_wing, right_wing}.
aar_geometry::TriangleMesh MakeUavMesh(const UavModelOptions& options = {});

// The UAV's refueling receptacle on the upper fuselage ahead of the wing [m], body frame.
Eigen::Vector3d UavReceptacleInReceiver();

// T_body_station: fuselage-station coordinates (x aft from the nose tip, y right, z up [m])
// into the UAV's body frame.
Eigen::Isometry3d UavStationToBody();

}  // namespace aar_description
