#pragma once

#include <string>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// Closed, outward-wound primitives centred on the origin with shared vertices (so adjacency is
// complete without welding), each as one part. Axes and sizes follow URDF's geometry elements.

// size: full edge lengths along x, y, z [m]. 8 vertices, 12 triangles.
TriangleMesh MakeBox(const Eigen::Vector3d& size, const std::string& part = "box");

// Axis along z, from -length/2 to +length/2 [m]; `segments` around (at least 3).
TriangleMesh MakeCylinder(double radius, double length, int segments = 32,
                          const std::string& part = "cylinder");

// Icosphere: an icosahedron subdivided `subdivisions` times (20 * 4^n triangles).
TriangleMesh MakeSphere(double radius, int subdivisions = 2, const std::string& part = "sphere");

}  // namespace aar_geometry
