// bench_boom_cost: where the boom's cost comes from (issue 29). Frames of an approach in each
// region (default approach, or AAR_FLIGHT_PATH), rendered twice with the same sensor noise (read
// noise 2 grey levels, the suite's), with the boom and with it hidden, through aar_stereo's thesis
// settings (block matching, every 8th point). Each cloud point takes its class from the
// renderer's label image at its pixel. Three occlusion configurations, each at the true pose:
//   no_boom  the boom hidden and not modelled (flight_no_boom's occlusion stage): nothing culled,
//            the reference hides only what the receiver hides of itself
//   dynamic  volumes culling (10 cm up to the far side, 2 cm outline at any depth) and the dynamic
//            reference: the thesis's experiment 3 as we run it, and flight's occlusion stage
//   margin   dynamic's culling with a depth margin (cull_depth_coefficient 0.0009: the far side
//            moved back by half a pixel of disparity, 0.0009 Z^2, along each ray)
// Per region and configuration, per frame: receiver and boom points in the cloud, boom points
// kept (escaped culling) and receiver points culled; kept points whose range is wrong (off the
// renderer's depth at their pixel by more than 0.3 m and 4 sigma_Z, sigma_d = 0.36 px) and of
// those the ones within 6 px of a boom pixel (the boom's disparity smeared onto its neighbours);
// reference samples ICP registers to (seen by both cameras; the drop from no_boom is what the
// boom hides); boom points within 1 m of the reference (pairs ICP would make); then ICP from the
// truth on the kept points (tracking's settings, at most 3,000 points) with point-to-point
// (flight's) and with stereo rays: the estimate's offset along the receiver's x and along the line
// of sight [cm]. The counts say which points the boom adds or takes; the offsets, what they do to
// one frame's registration, before any tracker (flight's outline is not in it).
//   bench_boom_cost [FRAMES_PER_REGION]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_geometry/pose_error.h>
#include <aar_occlusion/occlusion_step.h>
#include <aar_registration/icp.h>
#include <aar_testing/sim_stereo.h>
#include <opencv2/imgproc.hpp>

namespace {

using aar_sim::Label;

struct Config {
  const char* name;
  bool boom;                 // rendered and modelled
  double depth_coefficient;  // [1/m] the cull's depth margin
};

// Sums over a region's frames of one configuration.
struct Counts {
  int frames = 0;
  double receiver = 0, boom = 0, boom_kept = 0, receiver_culled = 0, reference = 0, boom_pairs = 0,
         misplaced = 0, misplaced_near_boom = 0;
  double p2p_x = 0, p2p_los = 0, rays_x = 0, rays_los = 0;  // [m] sums of |offset|
};

// The offset of ICP's estimate from the truth when the kept points (receiver frame at the truth)
// are registered from the truth: x of the receiver frame and along the line of sight [m].
void IcpOffsets(const aar_registration::Icp& icp, const std::vector<Eigen::Vector3d>& sensed,
                const Eigen::Vector3d& eye, const Eigen::Vector3d& line_of_sight, double* x,
                double* los) {
  const auto r = icp.Align(sensed, Eigen::Isometry3d::Identity(), &eye);
  const Eigen::Vector3d offset = r.T_target_source.inverse().translation();
  *x += std::abs(offset.x());
  *los += std::abs(offset.dot(line_of_sight));
}

// One frame of one configuration into `c`.
void CountFrame(const aar_testing::SimStereoFrame& f, const aar_testing::SimStereo& sim,
                aar_occlusion::OcclusionStep& step, aar_registration::Icp& p2p,
                aar_registration::Icp& rays, Counts& c) {
  aar_occlusion::OcclusionInput in;
  in.points = f.points_in_tanker;
  in.left_eye = sim.left_eye();
  in.right_eye = sim.right_eye();
  in.T_tanker_links = f.rendered.T_tanker_links;
  in.T_tanker_receiver_predicted = f.rendered.T_tanker_receiver;
  const aar_occlusion::OcclusionResult r = step.Process(in);
  const auto label = [&](size_t i) {
    const int pixel = f.stereo.cloud.pixel[i];
    return pixel < 0 ? Label::kBackground : static_cast<Label>(f.rendered.left.label.data[pixel]);
  };
  for (size_t i = 0; i < in.points.size(); ++i) {
    c.receiver += label(i) == Label::kReceiver;
    c.boom += label(i) == Label::kBoom;
  }
  for (const size_t i : r.removed) c.receiver_culled += label(i) == Label::kReceiver;
  // Pixels within 6 px of the boom: where a 9 px block straddling its edge gives its disparity.
  const auto& k = sim.rig().intrinsics;
  cv::Mat boom_mask(k.height, k.width, CV_8UC1);
  for (int p = 0; p < k.width * k.height; ++p)
    boom_mask.data[p] =
        f.rendered.left.label.data[p] == static_cast<uint8_t>(Label::kBoom) ? 255 : 0;
  cv::dilate(boom_mask, boom_mask, cv::Mat::ones(13, 13, CV_8UC1));
  const double fB = sim.geometry().fx * sim.geometry().baseline();
  for (const size_t i : r.kept) {
    const int pixel = f.stereo.cloud.pixel[i];
    const double z_true = pixel < 0 ? 0.0 : f.rendered.left.depth.data[pixel];
    if (!(z_true > 0.0)) continue;
    const double error = std::abs(f.stereo.cloud.xyz[i].z() - z_true);
    if (error <= std::max(0.3, 4.0 * 0.36 / fB * z_true * z_true)) continue;
    ++c.misplaced;
    c.misplaced_near_boom += boom_mask.data[pixel] != 0;
  }
  std::vector<Eigen::Vector3d> reference, normals;
  for (size_t i = 0; i < r.reference.cloud.size(); ++i) {
    if (r.reference.classes[i] != aar_occlusion::Visibility::kBoth) continue;
    reference.push_back(r.reference.cloud.points[i]);
    normals.push_back(r.reference.cloud.normals[i]);
  }
  c.reference += reference.size();
  const Eigen::Isometry3d T_receiver_tanker = f.rendered.T_tanker_receiver.inverse();
  std::vector<Eigen::Vector3d> sensed;
  for (const size_t i : r.kept) {
    const Eigen::Vector3d p = T_receiver_tanker * in.points[i];
    sensed.push_back(p);
    if (label(i) != Label::kBoom) continue;
    ++c.boom_kept;
    double nearest = 1e9;
    for (const auto& q : reference) nearest = std::min(nearest, (q - p).squaredNorm());
    c.boom_pairs += nearest <= 1.0;
  }
  std::shuffle(sensed.begin(), sensed.end(), std::mt19937(1));
  if (sensed.size() > 3000) sensed.resize(3000);
  ++c.frames;
  if (reference.size() < 10 || sensed.size() < 10) return;
  const Eigen::Vector3d eye = T_receiver_tanker * sim.left_eye();
  const Eigen::Vector3d los = -eye.normalized();  // the receiver's origin from the eye
  p2p.SetTarget(reference, normals);
  rays.SetTarget(reference, normals);
  IcpOffsets(p2p, sensed, eye, los, &c.p2p_x, &c.p2p_los);
  IcpOffsets(rays, sensed, eye, los, &c.rays_x, &c.rays_los);
}

// `frames` times of the path evenly spread over the part in `region`.
std::vector<double> TimesIn(const aar_sim::FlightPath& path, aar_geometry::Region region,
                            int frames) {
  std::vector<double> inside;
  for (double t = path.start_time(); t <= path.end_time(); t += 0.1) {
    const double range = path.At(t).T_tanker_receiver().translation().norm();
    if (aar_geometry::RegionOfRange(range) == region) inside.push_back(t);
  }
  std::vector<double> out;
  for (int k = 0; k < frames && !inside.empty(); ++k)
    out.push_back(inside[(inside.size() - 1) * (2 * k + 1) / (2 * frames)]);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::stoi(argv[1]) : 4;
  const Config configs[] = {
      {"no_boom", false, 0.0}, {"dynamic", true, 0.0}, {"margin", true, 0.0009}};
  try {
    const auto path = aar_sim::FlightPath::Load(std::getenv("AAR_FLIGHT_PATH")
                                                    ? std::getenv("AAR_FLIGHT_PATH")
                                                    : aar_testing::DefaultApproachPath());
    aar_sim::WorldOptions with = aar_testing::SimStereo::DefaultWorld();
    with.sensor.noise_stddev = 2.0;  // the suite's
    aar_sim::WorldOptions without = with;
    without.boom_visible = false;
    aar_testing::SimStereo sim_with(with), sim_without(without);
    aar_registration::IcpOptions icp;  // config/experiments/tracking.yaml's
    icp.max_correspondence_distance = 1.0;
    icp.min_rms_improvement = 1e-5;
    icp.stop_on_rms_rise = false;
    aar_registration::Icp p2p(icp);
    icp.metric = aar_registration::IcpMetric::kStereoRays;
    aar_registration::Icp rays(icp);
    std::printf("%-6s %-8s %6s %9s %7s %9s %10s %9s %9s %9s %10s %8s %8s %8s %8s\n", "region",
                "config", "frames", "receiver", "boom", "boom kept", "rcv culled", "misplaced",
                "near boom", "reference", "boom pairs", "p2p |x|", "p2p los", "rays |x|",
                "rays los");
    for (const auto region :
         {aar_geometry::Region::kA, aar_geometry::Region::kB, aar_geometry::Region::kC}) {
      const std::vector<double> times = TimesIn(path, region, frames);
      for (const Config& config : configs) {
        aar_occlusion::OcclusionStepOptions options;
        options.model_boom = config.boom;
        options.boom.cull_depth_coefficient = config.depth_coefficient;
        aar_testing::SimStereo& sim = config.boom ? sim_with : sim_without;
        aar_occlusion::OcclusionStep step(options, aar_testing::LoadBoomModel(), "",
                                          &sim.world().receiver_mesh());
        Counts c;
        for (size_t k = 0; k < times.size(); ++k) {
          const auto row = path.At(times[k]);
          const auto f = sim.Run(row, row.boom.value_or(aar_description::DefaultBoomPose()),
                                 1000 + k, true, true);
          CountFrame(f, sim, step, p2p, rays, c);
        }
        const double n = std::max(1, c.frames);
        std::printf(
            "%-6s %-8s %6d %9.0f %7.0f %9.1f %10.1f %9.1f %9.1f %9.0f %10.1f %8.2f %8.2f %8.2f "
            "%8.2f\n",
            aar_geometry::RegionName(region).c_str(), config.name, c.frames, c.receiver / n,
            c.boom / n, c.boom_kept / n, c.receiver_culled / n, c.misplaced / n,
            c.misplaced_near_boom / n, c.reference / n, c.boom_pairs / n, 100 * c.p2p_x / n,
            100 * c.p2p_los / n, 100 * c.rays_x / n, 100 * c.rays_los / n);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_boom_cost: %s\n", e.what());
    return 1;
  }
  return 0;
}
