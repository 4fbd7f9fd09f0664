// Cull method names, apart from the culling itself: option loading needs no geometry.
#include <stdexcept>

#include "aar_occlusion/boom.h"

namespace aar_occlusion {

CullMethod ParseCullMethod(const std::string& name) {
  if (name == "none") return CullMethod::kNone;
  if (name == "rays_brute") return CullMethod::kRaysBrute;
  if (name == "rays_bvh") return CullMethod::kRaysBvh;
  if (name == "volumes") return CullMethod::kVolumes;
  throw std::invalid_argument("cull method must be none, rays_brute, rays_bvh or volumes, not '" +
                              name + "'");
}

std::string ToString(CullMethod method) {
  switch (method) {
    case CullMethod::kNone:
      return "none";
    case CullMethod::kRaysBrute:
      return "rays_brute";
    case CullMethod::kRaysBvh:
      return "rays_bvh";
    case CullMethod::kVolumes:
      return "volumes";
  }
  return "?";
}

}  // namespace aar_occlusion
