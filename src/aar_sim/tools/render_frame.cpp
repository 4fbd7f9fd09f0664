// render_frame: renders one stereo pair of a flight path to PGM files, for looking at the world.
//   render_frame FLIGHT_PATH TIME_S OUT_PREFIX [--no-boom] [--background sea|terrain]
//                [--clouds COVERAGE] [--sun AZIMUTH_DEG,ELEVATION_DEG] [--no-shadows]
//                [--shadow-map TEXELS] [--propellers blades|disc] [--exposure SECONDS]
// --exposure turns motion blur on over that exposure (the propellers' blades smear over it too).
#include <fstream>
#include <iostream>

#include <aar_description/boom_model.h>
#include <ros/package.h>

#include "aar_sim/world.h"

namespace {

void WritePgm(const std::string& path, const aar_sim::Image<uint8_t>& image, int scale = 1) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << image.width << " " << image.height << "\n255\n";
  for (uint8_t v : image.data) out.put(static_cast<char>(v * scale));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: render_frame FLIGHT_PATH TIME_S OUT_PREFIX [--no-boom] "
                 "[--background sea|terrain] [--clouds COVERAGE] [--sun AZ_DEG,EL_DEG] "
                 "[--no-shadows] [--shadow-map TEXELS] [--propellers blades|disc] "
                 "[--exposure SECONDS]\n";
    return 2;
  }
  try {
    aar_sim::WorldOptions options =
        aar_sim::DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
    for (int i = 4; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--no-boom") {
        options.boom_visible = false;
      } else if (a == "--background" && i + 1 < argc) {
        const std::string b = argv[++i];
        if (b != "sea" && b != "terrain") throw std::runtime_error("--background: sea or terrain");
        options.renderer.scene.background =
            b == "sea" ? aar_sim::Background::kSea : aar_sim::Background::kTerrain;
      } else if (a == "--clouds" && i + 1 < argc) {
        options.renderer.scene.cloud_coverage = std::stod(argv[++i]);
      } else if (a == "--sun" && i + 1 < argc) {
        const std::string v = argv[++i];
        const size_t comma = v.find(',');
        if (comma == std::string::npos)
          throw std::runtime_error("--sun: AZIMUTH_DEG,ELEVATION_DEG");
        options.renderer.sun.enabled = true;
        options.renderer.sun.azimuth_deg = std::stod(v.substr(0, comma));
        options.renderer.sun.elevation_deg = std::stod(v.substr(comma + 1));
      } else if (a == "--no-shadows") {
        options.renderer.sun.shadows = false;
      } else if (a == "--shadow-map" && i + 1 < argc) {
        options.renderer.sun.shadow_map_size = std::stoi(argv[++i]);
      } else if (a == "--propellers" && i + 1 < argc) {
        const std::string p = argv[++i];
        if (p != "blades" && p != "disc") throw std::runtime_error("--propellers: blades or disc");
        options.propellers =
            p == "disc" ? aar_sim::PropellerMode::kDisc : aar_sim::PropellerMode::kBlades;
      } else if (a == "--exposure" && i + 1 < argc) {
        options.sensor.motion_blur = true;
        options.sensor.exposure_time = std::stod(argv[++i]);
      } else {
        std::cerr << "render_frame: unknown argument " << a << "\n";
        return 2;
      }
    }
    aar_sim::World world(options);
    const auto path = aar_sim::FlightPath::Load(argv[1], {world.boom_model().joints});
    const auto row = path.At(std::stod(argv[2]));
    const auto row_end = path.At(row.t + options.sensor.exposure_time);
    const aar_sim::SceneState end{row_end,
                                  row_end.boom.value_or(aar_description::DefaultBoomPose())};
    const auto frame = world.Render(row, row.boom.value_or(aar_description::DefaultBoomPose()), 0,
                                    true, false, options.sensor.motion_blur ? &end : nullptr);
    const std::string prefix = argv[3];
    WritePgm(prefix + "_left.pgm", frame.left.image);
    WritePgm(prefix + "_right.pgm", frame.right.image);
    WritePgm(prefix + "_label.pgm", frame.left.label, 50);
    std::cout << "range " << row.position_m.norm() << " m, renderer "
              << world.renderer().gl_renderer() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "render_frame: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
