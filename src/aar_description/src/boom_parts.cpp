#include "aar_description/boom_parts.h"

#include <stdexcept>

#include <aar_geometry/weld.h>

namespace aar_description {

std::vector<BoomCollisionPart> LoadBoomCollisionParts(const aar_geometry::RobotModel& model) {
  std::vector<BoomCollisionPart> parts;
  for (const auto& link : model.links) {
    if (link.collisions.empty() && !link.visuals.empty()) {
      throw std::invalid_argument("boom link '" + link.name +
                                  "' has visual but no collision geometry: it would hide the "
                                  "receiver without shadow volumes and its points would not be "
                                  "culled");
    }
    for (const auto& element : link.collisions) {
      BoomCollisionPart part;
      part.name = element.name;
      part.link = link.name;
      part.T_link_part = element.T_link_geometry;
      part.mesh = aar_geometry::WeldVertices(element.mesh).mesh;
      part.adjacency = aar_geometry::BuildAdjacency(part.mesh);
      const std::string where = "collision part '" + part.name + "' of boom link '" + link.name;
      if (!part.adjacency.closed()) {
        throw std::invalid_argument(where + "' is not closed (" + part.adjacency.NotClosedReason() +
                                    "): shadow volumes need closed convex parts");
      }
      // 0.1 mm: mesh files round vertices (6 decimals in OBJ), which tilts thin facets.
      if (!aar_geometry::IsConvex(part.mesh, 1e-4)) {
        throw std::invalid_argument(
            where + "' is not convex: point inclusion by planes needs convex parts");
      }
      parts.push_back(std::move(part));
    }
  }
  if (parts.empty())
    throw std::invalid_argument("boom model '" + model.name + "' has no collision geometry");
  return parts;
}

}  // namespace aar_description
