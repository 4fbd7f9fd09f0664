// bench_occlusion: the occlusion stage on the same simulated frames (default approach, boom in
// view, through aar_stereo's thesis settings), side by side: boom culling by brute-force rays,
// by rays through an Embree BVH and by point inclusion in volumes (points per second), the
// shadow-volume build per frame, and the dynamic reference model (self-occlusion by Embree, then
// the boom's shadow volumes) per frame. One thread throughout.
//   bench_occlusion [FRAMES] [REPEATS]
#include <cstdio>
#include <string>

#include <aar_description/boom_model.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_occlusion/boom.h>
#include <aar_occlusion/dynamic_reference.h>
#include <aar_testing/sim_stereo.h>
#include <aar_testing/timing.h>

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::stoi(argv[1]) : 8;
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 3;
  using aar_testing::MedianMs;
  using namespace aar_occlusion;
  try {
    aar_testing::SimStereo sim;
    aar_sim::World& world = sim.world();
    const auto path = aar_sim::FlightPath::Load(aar_testing::DefaultApproachPath());
    const auto model = aar_testing::LoadBoomModel();
    BoomOcclusion boom(LoadBoomParts(model));
    const Eigen::Vector3d left = sim.left_eye();
    const Eigen::Vector3d right = sim.right_eye();
    // Two reference densities: the default (400 samples per m^2) and about 20k samples.
    aar_geometry::ReferenceModelOptions dense_options, light_options;
    light_options.points_per_m2 = 127.0;
    DynamicReference dense(world.receiver_mesh(), dense_options);
    DynamicReference light(world.receiver_mesh(), light_options);

    std::printf("boom: %zu convex parts; reference samples: %zu (400/m^2) and %zu (127/m^2)\n",
                boom.parts().size(), dense.size(), light.size());
    std::printf("%5s %6s %6s | %10s %10s %10s %7s | %7s | %9s %9s %9s | %8s\n", "t[s]", "range",
                "points", "brute[ms]", "bvh[ms]", "vol[ms]", "brute/v", "build", "ref400", "ref127",
                "ref127c", "stage");
    double sum_brute = 0, sum_bvh = 0, sum_vol = 0, n_points = 0, worst_stage = 0;
    for (int i = 0; i < frames; ++i) {
      const double t =
          path.start_time() + (path.end_time() - path.start_time()) * (i + 0.5) / frames;
      const auto row = path.At(t);
      const std::vector<Eigen::Vector3d> points =
          sim.Run(row, aar_description::DefaultBoomPose(), i).points_in_tanker;
      const auto links = aar_geometry::ComputeLinkPoses(
          model, aar_description::BoomJointPositions(aar_description::DefaultBoomPose()));

      // The eye nudged by 1 mm each time: the build runs in full, as when the boom moves.
      double nudge = 0.0;
      const double build_ms = MedianMs(repeats, [&] {
        nudge += 1e-3;
        boom.Update(links, left + Eigen::Vector3d(nudge, 0, 0), right);
      });
      boom.Update(links, left, right);
      const double brute_ms = MedianMs(repeats, [&] { boom.Cull(points, CullMethod::kRaysBrute); });
      const double bvh_ms = MedianMs(repeats, [&] { boom.Cull(points, CullMethod::kRaysBvh); });
      const double vol_ms = MedianMs(repeats, [&] { boom.Cull(points, CullMethod::kVolumes); });
      const Eigen::Isometry3d T = row.T_tanker_receiver();
      // Self-occlusion from scratch every frame (reshell_distance 0 and a moved pose).
      Eigen::Isometry3d nudged = T;
      auto build_ref = [&](DynamicReference& ref) {
        nudged.translation().x() += 1e-3;
        ref.Build(nudged, boom);
      };
      const double ref400_ms = MedianMs(repeats, [&] { build_ref(dense); });
      const double ref127_ms = MedianMs(repeats, [&] { build_ref(light); });
      // Self-occlusion kept (the eyes moved less than reshell_distance): the boom classes only.
      DynamicReferenceOptions cached_options;
      cached_options.reshell_distance = 0.5;
      DynamicReference cached(world.receiver_mesh(), light_options, cached_options);
      cached.Build(T, boom);
      const double ref127c_ms = MedianMs(repeats, [&] { cached.Build(T, boom); });
      const double stage = build_ms + vol_ms + ref127_ms;
      worst_stage = std::max(worst_stage, stage);
      std::printf(
          "%5.1f %6.1f %6zu | %10.2f %10.3f %10.3f %6.0fx | %7.2f | %9.2f %9.2f %9.2f | %8.2f\n", t,
          row.position_m.norm(), points.size(), brute_ms, bvh_ms, vol_ms,
          brute_ms / std::max(vol_ms, 1e-6), build_ms, ref400_ms, ref127_ms, ref127c_ms, stage);
      sum_brute += brute_ms;
      sum_bvh += bvh_ms;
      sum_vol += vol_ms;
      n_points += points.size();
    }
    std::printf(
        "\npoints per second: brute-force rays %.3g, BVH rays %.3g, volumes %.3g; volumes "
        "%.0fx brute force, %.1fx BVH\n",
        n_points / sum_brute * 1e3, n_points / sum_bvh * 1e3, n_points / sum_vol * 1e3,
        sum_brute / sum_vol, sum_bvh / sum_vol);
    std::printf(
        "stage = volume build + volume culling + reference at 127/m^2 with self-occlusion "
        "each frame; worst frame %.2f ms\n",
        worst_stage);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_occlusion: %s\n", e.what());
    return 1;
  }
  return 0;
}
