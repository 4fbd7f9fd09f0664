#pragma once

#include <string>
#include <vector>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/triangle_mesh.h>

#include <Eigen/Geometry>

namespace aar_description {

// One closed convex collision element of the boom, welded, in its own frame: the boom as every
// stage sees it (occlusion's shadow and cull volumes grow it; the outline masks its projection).
struct BoomCollisionPart {
  std::string name;  // the collision element's name
  std::string link;
  Eigen::Isometry3d T_link_part = Eigen::Isometry3d::Identity();
  aar_geometry::TriangleMesh mesh;
  aar_geometry::TriangleAdjacency adjacency;
};

// Every collision element of the boom's model. Throws std::invalid_argument naming the link: a
// link with visual geometry but no collision geometry (it would hide the receiver and never be
// culled), a part that is open, inconsistently wound or not convex, or a model without any
// collision geometry.
std::vector<BoomCollisionPart> LoadBoomCollisionParts(const aar_geometry::RobotModel& model);

}  // namespace aar_description
