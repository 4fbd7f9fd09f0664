// The sun's options (renderer.h): its direction and the check of its settings.
#include <cmath>
#include <stdexcept>
#include <string>

#include "aar_sim/renderer.h"

namespace aar_sim {

Eigen::Vector3d SunOptions::DirectionInTanker() const {
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  // Bearing clockwise seen from above: towards the right wing is -y in the tanker frame.
  return {std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), std::sin(el)};
}

void SunOptions::Validate() const {
  auto check = [](bool ok, const char* key, const std::string& what) {
    if (!ok) throw std::invalid_argument(std::string(key) + " " + what);
  };
  check(elevation_deg > 0.0 && elevation_deg <= 90.0, "sun_elevation_deg",
        "must be in (0, 90]: a sun at or below the horizon lights nothing from above (got " +
            std::to_string(elevation_deg) + ")");
  check(std::isfinite(azimuth_deg), "sun_azimuth_deg", "must be a finite angle");
  check(direct > 0.0 && direct <= 4.0, "sun_direct", "must be in (0, 4]");
  check(ambient >= 0.0 && ambient <= 2.0, "sun_ambient", "must be in [0, 2]");
  check(shadow_map_size >= 64 && shadow_map_size <= 8192, "sun_shadow_map_size",
        "must be from 64 to 8192 texels");
  check(paint_specular >= 0.0, "sun_paint_specular", "must not be negative");
  check(metal_specular >= 0.0, "sun_metal_specular", "must not be negative");
  check(glass_specular >= 0.0, "sun_glass_specular", "must not be negative");
}

}  // namespace aar_sim
