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

}  // namespace aar_description
