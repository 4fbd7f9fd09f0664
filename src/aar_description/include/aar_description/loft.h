#pragma once

#include <vector>

#include <aar_geometry/triangle_mesh.h>

namespace aar_description {

using Ring = std::vector<Eigen::Vector3d>;

// Appends a tube through `rings` (all of one size, ordered around) to `mesh` as part `part`,
// wound so that normals point away from each ring's centroid; caps the first and last ring when
// asked. Adjacent rings share vertices, so the result needs no welding.
void AppendLoft(aar_geometry::TriangleMesh& mesh, const std::string& part,
                const std::vector<Ring>& rings, bool cap_first, bool cap_last);

// A superellipse ring in the plane x = x0, centred at (x0, y0, z0) with half-axes a (along y)
// and b (along z); exponent 2 is an ellipse, larger is boxier.
Ring SuperellipseRing(double x0, double y0, double z0, double a, double b, double exponent,
                      int segments);

// Closed symmetric airfoil (NACA 4-digit thickness, closed trailing edge), `points` per surface,
// in chord-local (u along chord 0..1 from the leading edge, v across thickness) coordinates
// scaled by chord; returned as (u, v) pairs ordered around the section.
std::vector<Eigen::Vector2d> AirfoilSection(double chord, double thickness_ratio, int points);

}  // namespace aar_description
