#include "aar_alignment/boom_parts.h"

namespace aar_alignment {

std::vector<std::vector<Eigen::Vector3d>> BoomPartsInTanker(
    const std::vector<aar_occlusion::BoomPart>& parts,
    const std::map<std::string, Eigen::Isometry3d>& T_tanker_links) {
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (const aar_occlusion::BoomPart& part : parts) {
    const auto link = T_tanker_links.find(part.link);
    if (link == T_tanker_links.end()) continue;
    const Eigen::Isometry3d T = link->second * part.T_link_part;
    std::vector<Eigen::Vector3d> vertices;
    vertices.reserve(part.mesh.vertices.size());
    for (const auto& v : part.mesh.vertices) vertices.push_back(T * v);
    out.push_back(std::move(vertices));
  }
  return out;
}

}  // namespace aar_alignment
