// render_frame: renders one stereo pair of a flight path to PGM files, for looking at the world.
//   render_frame FLIGHT_PATH TIME_S OUT_PREFIX [--no-boom] [--background sea|terrain]
//                [--clouds COVERAGE]
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
                 "[--background sea|terrain] [--clouds COVERAGE]\n";
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
      } else {
        std::cerr << "render_frame: unknown argument " << a << "\n";
        return 2;
      }
    }
    aar_sim::World world(options);
    const auto path = aar_sim::FlightPath::Load(argv[1], {world.boom_model().joints});
    const auto row = path.At(std::stod(argv[2]));
    const auto frame =
        world.Render(row, row.boom.value_or(aar_description::DefaultBoomPose()), 0, true, false);
    const std::string prefix = argv[3];
    WritePgm(prefix + "_left.pgm", frame.left.image);
    WritePgm(prefix + "_right.pgm", frame.right.image);
    WritePgm(prefix + "_label.pgm", frame.left.label, 60);
    std::cout << "range " << row.position_m.norm() << " m, renderer "
              << world.renderer().gl_renderer() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "render_frame: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
