// bench_render: stereo pairs rendered per second at the configured resolution, along the default
// approach (far, mid and near frames): images only, with label + depth read back, with the label
// and the receiver's visibility (World::MeasureVisibility, what the lockstep simulator adds per
// frame since issue 44), and with every sensor effect on (config/realism/sensor.yaml's values: shot
// and read noise, motion blur over 2 ms with the path's motion, gain mismatch, auto-exposure) side
// by side with them off.
//   bench_render FLIGHT_PATH [PAIRS_PER_POINT]
// AAR_BENCH_NOISE: the read noise of the first two columns [grey levels] (default 2).
// AAR_BENCH_SCENE=1 adds four columns with issue 16's effects, rendered in the same run: the
// background (terrain, clouds 0.4: config/realism/background.yaml) alone and with the sensor
// effects; the sun with shadows and the propellers (sun.yaml, propellers.yaml) with the sensor
// effects; and everything at once (config/realism/realistic.yaml's renderer and sensor settings).
// AAR_BENCH_SHADOW_MAP: the sun's shadow-map size in those two columns (0: no shadows).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include <aar_description/boom_model.h>
#include <ros/package.h>

#include "aar_sim/world.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_render FLIGHT_PATH [PAIRS_PER_POINT]\n";
    return 2;
  }
  const std::string path_file = argv[1];
  const int pairs = argc > 2 ? std::stoi(argv[2]) : 20;
  try {
    aar_sim::WorldOptions options =
        aar_sim::DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
    options.sensor.noise_stddev =
        std::getenv("AAR_BENCH_NOISE") ? std::stod(std::getenv("AAR_BENCH_NOISE")) : 2.0;
    aar_sim::World world(options);
    aar_sim::WorldOptions realistic = options;  // config/realism/sensor.yaml
    aar_sim::SensorOptions& sensor = realistic.sensor;
    sensor.noise_stddev = 2.0;
    sensor.full_well = 10000.0;
    sensor.motion_blur = true;
    sensor.exposure_time = 0.002;
    sensor.gain_mismatch = 0.03;
    sensor.auto_exposure = true;
    aar_sim::World sensed(realistic);
    const bool scene = std::getenv("AAR_BENCH_SCENE") != nullptr;
    std::unique_ptr<aar_sim::World> scene_world, scene_sensed, sun_world, all_world;
    if (scene) {
      aar_sim::WorldOptions o = options;
      o.renderer.scene.background = aar_sim::Background::kTerrain;
      o.renderer.scene.cloud_coverage = 0.4;
      scene_world = std::make_unique<aar_sim::World>(o);
      o.sensor = realistic.sensor;
      scene_sensed = std::make_unique<aar_sim::World>(o);
      o.renderer.sun.enabled = true;
      if (const char* map = std::getenv("AAR_BENCH_SHADOW_MAP"))  // 0: no shadows
        std::atoi(map) > 0 ? void(o.renderer.sun.shadow_map_size = std::atoi(map))
                           : void(o.renderer.sun.shadows = false);
      o.propellers = aar_sim::PropellerMode::kBlades;
      all_world = std::make_unique<aar_sim::World>(o);
      o.renderer.scene = aar_sim::SceneOptions();
      sun_world = std::make_unique<aar_sim::World>(o);
    }
    const auto path = aar_sim::FlightPath::Load(path_file);
    std::printf("renderer: %s, %dx%d, %d pairs per point\n", world.renderer().gl_renderer().c_str(),
                options.rig.intrinsics.width, options.rig.intrinsics.height, pairs);
    std::printf("%10s %12s %16s %22s %27s %18s%s\n", "range [m]", "t [s]", "pairs/s (images)",
                "pairs/s (+label+depth)", "pairs/s (+label+visibility)", "pairs/s (+sensor)",
                scene ? " pairs/s (+scene) (+scene+sensor) (+sun+props+sensor) (everything)" : "");
    for (double fraction : {0.0, 0.5, 0.8, 1.0}) {
      const double t = path.start_time() + fraction * (path.end_time() - path.start_time());
      const auto row = path.At(t);
      const aar_sim::BoomPose boom = row.boom.value_or(aar_description::DefaultBoomPose());
      const auto row_end = path.At(t + sensor.exposure_time);
      const aar_sim::SceneState end{row_end,
                                    row_end.boom.value_or(aar_description::DefaultBoomPose())};
      aar_sim::World* worlds[7] = {
          &world,          &world,         &sensed, scene_world.get(), scene_sensed.get(),
          sun_world.get(), all_world.get()};
      double rate[7] = {0, 0, 0, 0, 0, 0, 0};
      for (int column = 0; column < (scene ? 7 : 3); ++column) {
        aar_sim::World& w = *worlds[column];
        const bool extra = column == 1;
        const aar_sim::SceneState* exposure_end = column == 2 || column >= 4 ? &end : nullptr;
        w.Render(row, boom, 0, extra, extra, exposure_end);  // warm-up (shader JIT)
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < pairs; ++i) w.Render(row, boom, i, extra, extra, exposure_end);
        rate[column] =
            pairs / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
      const auto start = std::chrono::steady_clock::now();
      for (int i = 0; i < pairs; ++i) world.MeasureVisibility(world.Render(row, boom, i, true));
      const double visibility =
          pairs / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%10.1f %12.1f %16.1f %22.1f %27.1f %18.1f", row.position_m.norm(), t, rate[0],
                  rate[1], visibility, rate[2]);
      if (scene) std::printf(" %16.1f %15.1f %19.1f %12.1f", rate[3], rate[4], rate[5], rate[6]);
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
