// bench_render: stereo pairs rendered per second at the configured resolution, along the default
// approach (far, mid and near frames), images only and with label + depth read back.
//   bench_render FLIGHT_PATH [PAIRS_PER_POINT]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
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
    options.renderer.noise_stddev =
        std::getenv("AAR_BENCH_NOISE") ? std::stod(std::getenv("AAR_BENCH_NOISE")) : 2.0;
    aar_sim::World world(options);
    const auto path = aar_sim::FlightPath::Load(path_file);
    std::printf("renderer: %s, %dx%d, %d pairs per point\n", world.renderer().gl_renderer().c_str(),
                options.rig.intrinsics.width, options.rig.intrinsics.height, pairs);
    std::printf("%10s %12s %16s %22s\n", "range [m]", "t [s]", "pairs/s (images)",
                "pairs/s (+label+depth)");
    for (double fraction : {0.0, 0.5, 0.8, 1.0}) {
      const double t = path.start_time() + fraction * (path.end_time() - path.start_time());
      const auto row = path.At(t);
      double rate[2];
      for (int extra = 0; extra < 2; ++extra) {
        world.Render(row, aar_description::DefaultBoomPose(), 0, extra,
                     extra);  // warm-up (shader JIT)
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < pairs; ++i)
          world.Render(row, aar_description::DefaultBoomPose(), i, extra, extra);
        rate[extra] =
            pairs / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
      std::printf("%10.1f %12.1f %16.1f %22.1f\n", row.position_m.norm(), t, rate[0], rate[1]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
