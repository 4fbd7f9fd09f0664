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

// Applies the option at argv[*i] to `options`, with its value (then *i is the value's index);
// false if it is not an option of render_frame (or lacks its value).
bool ApplyOption(int argc, char** argv, int* i, aar_sim::WorldOptions* options) {
  const std::string a = argv[*i];
  const bool has_value = *i + 1 < argc;
  auto value = [&] { return std::string(argv[++*i]); };
  if (a == "--no-boom") {
    options->boom_visible = false;
  } else if (a == "--background" && has_value) {
    const std::string b = value();
    if (b != "sea" && b != "terrain") throw std::runtime_error("--background: sea or terrain");
    options->renderer.scene.background =
        b == "sea" ? aar_sim::Background::kSea : aar_sim::Background::kTerrain;
  } else if (a == "--clouds" && has_value) {
    options->renderer.scene.cloud_coverage = std::stod(value());
  } else if (a == "--sun" && has_value) {
    const std::string v = value();
    const size_t comma = v.find(',');
    if (comma == std::string::npos) throw std::runtime_error("--sun: AZIMUTH_DEG,ELEVATION_DEG");
    options->renderer.sun.enabled = true;
    options->renderer.sun.azimuth_deg = std::stod(v.substr(0, comma));
    options->renderer.sun.elevation_deg = std::stod(v.substr(comma + 1));
  } else if (a == "--no-shadows") {
    options->renderer.sun.shadows = false;
  } else if (a == "--shadow-map" && has_value) {
    options->renderer.sun.shadow_map_size = std::stoi(value());
  } else if (a == "--propellers" && has_value) {
    const std::string p = value();
    if (p != "blades" && p != "disc") throw std::runtime_error("--propellers: blades or disc");
    options->propellers =
        p == "disc" ? aar_sim::PropellerMode::kDisc : aar_sim::PropellerMode::kBlades;
  } else if (a == "--exposure" && has_value) {
    options->sensor.motion_blur = true;
    options->sensor.exposure_time = std::stod(value());
  } else {
    return false;
  }
  return true;
}

// The stereo pair at TIME_S of the flight path (blurred over the exposure when motion blur is
// on): OUT_PREFIX_left.pgm, _right.pgm and _label.pgm (labels times 50).
void RenderFrame(const aar_sim::WorldOptions& options, const std::string& flight_path,
                 const std::string& time_s, const std::string& prefix) {
  aar_sim::World world(options);
  const auto path = aar_sim::FlightPath::Load(flight_path, {world.boom_model().joints});
  const auto row = path.At(std::stod(time_s));
  const auto row_end = path.At(row.t + options.sensor.exposure_time);
  const aar_sim::SceneState end{row_end, row_end.boom.value_or(aar_description::DefaultBoomPose())};
  const auto frame = world.Render(row, row.boom.value_or(aar_description::DefaultBoomPose()), 0,
                                  true, false, options.sensor.motion_blur ? &end : nullptr);
  WritePgm(prefix + "_left.pgm", frame.left.image);
  WritePgm(prefix + "_right.pgm", frame.right.image);
  WritePgm(prefix + "_label.pgm", frame.left.label, 50);
  std::cout << "range " << row.position_m.norm() << " m, renderer "
            << world.renderer().gl_renderer() << "\n";
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
      if (!ApplyOption(argc, argv, &i, &options)) {
        std::cerr << "render_frame: unknown argument " << argv[i] << "\n";
        return 2;
      }
    }
    RenderFrame(options, argv[1], argv[2], argv[3]);
  } catch (const std::exception& e) {
    std::cerr << "render_frame: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
