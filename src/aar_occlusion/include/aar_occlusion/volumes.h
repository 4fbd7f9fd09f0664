#pragma once

#include <string>
#include <vector>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/triangle_mesh.h>

namespace aar_occlusion {

// A plane with unit outward normal: a point p is inside when normal . p <= offset (thesis Eq. 6,
// offset = point_on_plane . normal).
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;  // [m]

  double SignedDistance(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

// The intersection of half-spaces: convex, possibly unbounded.
struct ConvexVolume {
  std::vector<Plane> planes;

  // Inside every plane, allowing `margin` [m] outside each (a grown volume).
  bool Contains(const Eigen::Vector3d& p, double margin = 0.0) const {
    for (const auto& plane : planes) {
      if (plane.SignedDistance(p) > margin) return false;
    }
    return true;
  }
  ConvexVolume Transformed(const Eigen::Isometry3d& T_new_old) const;
};

// A silhouette edge, directed as in its camera-facing triangle (counter-clockwise seen from the
// eye), from vertex `from` to vertex `to`.
struct SilhouetteEdge {
  int from = -1;
  int to = -1;
};

// One closed convex part seen from an eye (thesis 3.8), everything in the part's frame.
struct PartView {
  std::vector<bool> facing;                // per triangle: faces the eye
  std::vector<SilhouetteEdge> silhouette;  // edges between facing and non-facing triangles
  ConvexVolume cone;    // planes through the eye and each silhouette edge: all the part can hide
  ConvexVolume shadow;  // cone + behind every facing triangle: what the part hides (and itself)
  ConvexVolume light;   // cone + in front of every facing triangle's plane: between eye and part
};

// Throws std::invalid_argument unless `mesh` (welded) is closed, consistently wound and convex
// (checked when `validate`; callers that validated the part once, as LoadBoomParts does, skip
// the O(triangles x vertices) check per frame), naming `part`; the eye must be outside the part.
PartView ViewPart(const aar_geometry::TriangleMesh& mesh,
                  const aar_geometry::TriangleAdjacency& adjacency, const Eigen::Vector3d& eye,
                  const std::string& part = "part", bool validate = true);

// The shadow volume as triangles for display: the camera-facing triangles (the cap) and each
// silhouette edge extruded `length` [m] away from the eye. In the part's frame.
aar_geometry::TriangleMesh ShadowVolumeMesh(const aar_geometry::TriangleMesh& mesh,
                                            const PartView& view, const Eigen::Vector3d& eye,
                                            double length);

// Per point, seen by each of two eyes through a set of occluders' shadow volumes.
enum class Visibility : uint8_t { kBoth = 0, kLeftOnly = 1, kRightOnly = 2, kNeither = 3 };

// A point is hidden from an eye when it lies inside any of that eye's shadow volumes; a
// non-finite point is kNeither.
std::vector<Visibility> Classify(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<ConvexVolume>& left_shadows,
                                 const std::vector<ConvexVolume>& right_shadows);

}  // namespace aar_occlusion
