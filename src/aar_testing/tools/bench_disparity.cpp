// bench_disparity: block matching's disparity error on the receiver against the renderer's
// truth, with the sensor model's parts on one at a time, side by side on the same frames
// (issue 16: the realistic preset's region C position cost is a range bias; is it the matcher's
// sub-pixel estimate?). Frames near contact on the default approach (or AAR_FLIGHT_PATH), thesis
// stereo settings; on receiver pixels at least 5 px inside its outline (no depth edge under the
// 9 px block), error = measured disparity - f B / depth (and its range offset at their mean
// depth); on every receiver pixel; and the valid pixels just off its outline. Then each frame's
// cloud (every 8th point, the boom culled) is registered from the true pose against the dynamic
// reference built at the true pose, with tracking_robust's ICP (point-to-point, 1 m pairs, at
// most 3,000 points): the offset it settles at [cm, deg], receiver frame, is what stereo's points
// alone make ICP believe; and the same with point-to-plane, and with stereo rays (pairs along the
// camera rays, weighted by the noise along them: flight's ICP, issue 29) in x and pitch. Two rows
// change only the registered cloud of read-noise frames: zero-mean disparity noise along each ray,
// or a share of the points dropped at random (which of the two does the sensor model's harm?); the
// last two build it with aar_stereo's median_filter 5 (does less scatter undo it?).
//   bench_disparity [FRAMES] [FIRST_T] [LAST_T]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_geometry/pose.h>
#include <aar_occlusion/occlusion_step.h>
#include <aar_registration/icp.h>
#include <aar_testing/sim_stereo.h>
#include <opencv2/imgproc.hpp>

namespace {

struct Variant {
  const char* name;
  double read_noise;  // [grey levels]
  double full_well;   // [e-] 0: no shot noise
  bool auto_exposure;
  double gain_mismatch;
  // Synthetic, on the registered cloud only: disparity noise along each point's ray [px], and a
  // share of its points dropped at random.
  double extra_disparity_sd = 0.0;
  double drop = 0.0;
  int median = 0;  // [px] aar_stereo's median_filter for the registered cloud (0: off)
};

struct Stats {
  double sum = 0, sum2 = 0;
  long n = 0;
  void Add(double e) { sum += e, sum2 += e * e, ++n; }
  double mean() const { return n ? sum / n : NAN; }
  double sd() const { return n > 1 ? std::sqrt(std::max(0.0, sum2 / n - mean() * mean())) : NAN; }
};

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::stoi(argv[1]) : 12;
  const double first_t = argc > 2 ? std::stod(argv[2]) : 46.0;
  const double last_t = argc > 3 ? std::stod(argv[3]) : 51.0;
  // config/realism/sensor.yaml's values over the suite's read noise of 2 grey levels; the last
  // row, more read noise instead of shot noise (at grey 128 shot noise adds about 1.8 levels).
  const Variant variants[] = {{"read noise only", 2.0, 0.0, false, 0.0},
                              {"+ shot noise", 2.0, 10000.0, false, 0.0},
                              {"+ auto-exposure", 2.0, 0.0, true, 0.0},
                              {"+ gain mismatch", 2.0, 0.0, false, 0.03},
                              {"sensor.yaml (no blur)", 2.0, 10000.0, true, 0.03},
                              {"read noise 3 (no shot)", 3.0, 0.0, false, 0.0},
                              {"read noise, +0.2 px on rays", 2.0, 0.0, false, 0.0, 0.2, 0.0},
                              {"read noise, 19 % dropped", 2.0, 0.0, false, 0.0, 0.0, 0.19},
                              {"read noise, median 5", 2.0, 0.0, false, 0.0, 0.0, 0.0, 5},
                              {"sensor.yaml, median 5", 2.0, 10000.0, true, 0.03, 0.0, 0.0, 5}};
  try {
    const auto path = aar_sim::FlightPath::Load(std::getenv("AAR_FLIGHT_PATH")
                                                    ? std::getenv("AAR_FLIGHT_PATH")
                                                    : aar_testing::DefaultApproachPath());
    std::printf("%-28s %9s %10s %8s %11s %9s %10s %8s %9s %10s %11s %10s %10s\n", "sensor",
                "interior", "mean[px]", "sd[px]", "range[cm]", "receiver", "mean[px]", "outline",
                "icp x[cm]", "pitch[deg]", "plane x[cm]", "rays x[cm]", "rays pitch");
    for (const Variant& v : variants) {
      aar_sim::WorldOptions w = aar_testing::SimStereo::DefaultWorld();
      w.sensor.noise_stddev = v.read_noise;
      w.sensor.full_well = v.full_well;
      w.sensor.auto_exposure = v.auto_exposure;
      w.sensor.gain_mismatch = v.gain_mismatch;
      aar_stereo::StereoOptions options;
      options.decimation = aar_stereo::Decimation::kNone;
      aar_testing::SimStereo sim(w, options);
      aar_stereo::StereoOptions every8th;  // the thesis's decimation, as the pipeline
      every8th.median_filter = v.median;
      const aar_stereo::StereoProcessor decimated(every8th);
      aar_occlusion::OcclusionStepOptions occlusion;  // volumes; the dynamic reference
      aar_occlusion::OcclusionStep step(occlusion, aar_testing::LoadBoomModel(), "",
                                        &sim.world().receiver_mesh());
      aar_registration::IcpOptions icp_options;  // config/experiments/tracking_robust.yaml's
      icp_options.max_correspondence_distance = 1.0;
      icp_options.min_rms_improvement = 1e-5;
      icp_options.stop_on_rms_rise = false;
      aar_registration::Icp icp(icp_options);
      aar_registration::IcpOptions plane_options = icp_options;  // the same, point-to-plane
      plane_options.metric = aar_registration::IcpMetric::kPointToPlane;
      aar_registration::Icp icp_plane(plane_options);
      aar_registration::IcpOptions ray_options = icp_options;  // the same, pairs along the rays
      ray_options.metric = aar_registration::IcpMetric::kStereoRays;
      aar_registration::Icp icp_rays(ray_options);
      std::mt19937 rng(1), synth(2);
      Stats offset_x, offset_pitch, plane_x, rays_x,
          rays_pitch;  // [m], [deg] of the registered pose against the truth
      const double fB = sim.geometry().fx * sim.geometry().baseline();  // [px m]
      Stats stats, all, depth_m;  // interior, every receiver pixel, interior depth [m]
      long outline = 0;
      for (int i = 0; i < frames; ++i) {
        const double t = first_t + (last_t - first_t) * i / std::max(1, frames - 1);
        const aar_testing::SimStereoFrame f =
            sim.Run(path.At(t), aar_description::DefaultBoomPose(), 1000 + i, true, true);
        const auto& k = w.rig.intrinsics;
        {  // ICP from the truth on the decimated, culled cloud
          const aar_stereo::StereoResult cloud =
              decimated.Process(sim.Left(f.rendered), sim.Right(f.rendered), sim.geometry());
          aar_stereo::CloudPoints points = cloud.cloud;
          if (v.extra_disparity_sd > 0.0 || v.drop > 0.0) {
            std::normal_distribution<double> noise(0.0, v.extra_disparity_sd);
            std::uniform_real_distribution<double> uniform(0.0, 1.0);
            aar_stereo::CloudPoints kept;
            for (const Eigen::Vector3f& p : points.xyz) {
              if (v.drop > 0.0 && uniform(synth) < v.drop) continue;
              const double d = fB / p.z() + (v.extra_disparity_sd > 0.0 ? noise(synth) : 0.0);
              if (!(d > 0.0)) continue;
              kept.xyz.push_back(p * static_cast<float>(fB / d / p.z()));
            }
            points = kept;
          }
          aar_occlusion::OcclusionInput in;
          in.points = sim.ToTanker(points);
          in.left_eye = sim.left_eye();
          in.right_eye = sim.right_eye();
          in.T_tanker_links = f.rendered.T_tanker_links;
          in.T_tanker_receiver_predicted = f.rendered.T_tanker_receiver;
          const aar_occlusion::OcclusionResult r = step.Process(in);
          std::vector<Eigen::Vector3d> reference, normals;
          for (size_t i = 0; i < r.reference.cloud.size(); ++i) {
            if (r.reference.classes[i] != aar_occlusion::Visibility::kBoth) continue;
            reference.push_back(r.reference.cloud.points[i]);
            normals.push_back(r.reference.cloud.normals[i]);
          }
          std::vector<Eigen::Vector3d> sensed;  // receiver frame, at the truth
          const Eigen::Isometry3d T_receiver_tanker = f.rendered.T_tanker_receiver.inverse();
          for (const size_t i : r.kept) sensed.push_back(T_receiver_tanker * in.points[i]);
          std::shuffle(sensed.begin(), sensed.end(), rng);
          if (sensed.size() > 3000) sensed.resize(3000);
          icp.SetTarget(reference);
          const auto result = icp.Align(sensed, Eigen::Isometry3d::Identity());
          // T_target_source maps the sensed cloud onto the reference: the estimate is its
          // inverse applied to the truth, so the offset is its inverse's.
          const Eigen::Isometry3d offset = result.T_target_source.inverse();
          offset_x.Add(offset.translation().x());
          icp_plane.SetTarget(reference, normals);
          plane_x.Add(icp_plane.Align(sensed, Eigen::Isometry3d::Identity())
                          .T_target_source.inverse()
                          .translation()
                          .x());
          offset_pitch.Add(aar_geometry::RollPitchYawFromRotation(offset.linear()).pitch * 180.0 /
                           M_PI);
          icp_rays.SetTarget(reference, normals);
          const Eigen::Vector3d eye = T_receiver_tanker * sim.left_eye();
          const Eigen::Isometry3d rays =
              icp_rays.Align(sensed, Eigen::Isometry3d::Identity(), &eye).T_target_source.inverse();
          rays_x.Add(rays.translation().x());
          rays_pitch.Add(aar_geometry::RollPitchYawFromRotation(rays.linear()).pitch * 180.0 /
                         M_PI);
        }
        cv::Mat receiver(k.height, k.width, CV_8UC1);
        for (int p = 0; p < k.width * k.height; ++p)
          receiver.data[p] =
              f.rendered.left.label.data[p] == static_cast<uint8_t>(aar_sim::Label::kReceiver) ? 255
                                                                                               : 0;
        // Interior: no depth edge under the block. Outline: off the receiver, within 6 px of it
        // (where a 9 px block straddling the edge gives off-receiver pixels its disparity).
        cv::Mat interior, near;
        cv::erode(receiver, interior, cv::Mat::ones(11, 11, CV_8UC1));
        cv::dilate(receiver, near, cv::Mat::ones(13, 13, CV_8UC1));
        for (int r = 0; r < k.height; ++r) {
          for (int c = 0; c < k.width; ++c) {
            const int p = r * k.width + c;
            const float d = f.stereo.disparity.at<float>(r, c);
            const float z = f.rendered.left.depth.data[p];
            if (!(d > options.min_disparity)) continue;
            if (receiver.data[p] && z > 0.0f) all.Add(d - fB / z);
            outline += near.data[p] && !receiver.data[p];
            if (!interior.data[p] || !(z > 0.0f)) continue;
            stats.Add(d - fB / z);
            depth_m.Add(z);
          }
        }
      }
      // The range offset that mean disparity error makes at the mean depth: z^2 / (f B) * e.
      const double z = depth_m.mean();
      std::printf(
          "%-28s %9ld %10.4f %8.4f %11.2f %9ld %10.4f %8ld %9.2f %10.3f %11.2f %10.2f %10.3f\n",
          v.name, stats.n, stats.mean(), stats.sd(), -100.0 * z * z / fB * stats.mean(), all.n,
          all.mean(), outline, 100.0 * offset_x.mean(), offset_pitch.mean(), 100.0 * plane_x.mean(),
          100.0 * rays_x.mean(), rays_pitch.mean());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_disparity: %s\n", e.what());
    return 1;
  }
  return 0;
}
