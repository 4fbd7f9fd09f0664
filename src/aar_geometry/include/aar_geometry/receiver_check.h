#pragma once

#include <string>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// What a receiver model must be to be sampled, shelled and registered against: an aircraft-sized,
// closed surface in metres.
struct ReceiverCheckOptions {
  double min_extent = 1.0;    // [m] largest bounding-box side at least this (else: km? scale?)
  double max_extent = 100.0;  // [m] and at most this (the largest aircraft span 88 m; mm? inches?)
  // [m] open boundary allowed outside every other component of the mesh (a wing root buried in
  // the fuselage is fine; a missing fuselage panel is not).
  double max_exposed_open_length = 0.05;
  double weld_epsilon = 1e-4;  // [m] vertices this close are one (thesis)
};

struct ReceiverCheckResult {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // [m] bounding-box sides
  size_t open_edges = 0;                           // after welding
  size_t exposed_open_edges = 0;                   // of those, outside every other component
  double exposed_open_length = 0.0;                // [m]
};

// Throws LoadError("<path>: <reason>") for a mesh that has no faces, a non-finite vertex, a size
// outside [min_extent, max_extent] (the figure and the likely unit named), or an open boundary:
// edges used by one triangle whose midpoints lie outside every other connected component (by
// the generalised winding number), the count, length and one such edge's position named.
ReceiverCheckResult CheckReceiverMesh(const TriangleMesh& mesh, const std::string& path,
                                      const ReceiverCheckOptions& options = {});

}  // namespace aar_geometry
