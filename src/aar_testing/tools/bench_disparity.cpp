// bench_disparity: block matching's disparity error on the receiver against the renderer's
// truth, with the sensor model's parts on one at a time, side by side on the same frames
// (issue 16: the realistic preset's region C position cost is a range bias; is it the matcher's
// sub-pixel estimate?). Frames near contact on the default approach (or AAR_FLIGHT_PATH), thesis
// stereo settings; on receiver pixels at least 5 px inside its outline (no depth edge under the
// 9 px block), error = measured disparity - f B / depth (and its range offset at their mean
// depth); on every receiver pixel; and the valid pixels just off its outline.
//   bench_disparity [FRAMES] [FIRST_T] [LAST_T]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <aar_description/boom_model.h>
#include <aar_testing/sim_stereo.h>
#include <opencv2/imgproc.hpp>

namespace {

struct Variant {
  const char* name;
  double full_well;  // [e-] 0: no shot noise
  bool auto_exposure;
  double gain_mismatch;
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
  // config/realism/sensor.yaml's values; read noise 2 grey levels in every variant (the suite's).
  const Variant variants[] = {{"read noise only", 0.0, false, 0.0},
                              {"+ shot noise", 10000.0, false, 0.0},
                              {"+ auto-exposure", 0.0, true, 0.0},
                              {"+ gain mismatch", 0.0, false, 0.03},
                              {"sensor.yaml (no blur)", 10000.0, true, 0.03}};
  try {
    const auto path = aar_sim::FlightPath::Load(std::getenv("AAR_FLIGHT_PATH")
                                                    ? std::getenv("AAR_FLIGHT_PATH")
                                                    : aar_testing::DefaultApproachPath());
    std::printf("%-24s %9s %10s %8s %11s %9s %10s %8s\n", "sensor", "interior", "mean[px]",
                "sd[px]", "range[cm]", "receiver", "mean[px]", "outline");
    for (const Variant& v : variants) {
      aar_sim::WorldOptions w = aar_testing::SimStereo::DefaultWorld();
      w.sensor.noise_stddev = 2.0;
      w.sensor.full_well = v.full_well;
      w.sensor.auto_exposure = v.auto_exposure;
      w.sensor.gain_mismatch = v.gain_mismatch;
      aar_stereo::StereoOptions options;
      options.decimation = aar_stereo::Decimation::kNone;
      aar_testing::SimStereo sim(w, options);
      const double fB = sim.geometry().fx * sim.geometry().baseline();  // [px m]
      Stats stats, all, depth_m;  // interior, every receiver pixel, interior depth [m]
      long outline = 0;
      for (int i = 0; i < frames; ++i) {
        const double t = first_t + (last_t - first_t) * i / std::max(1, frames - 1);
        const aar_testing::SimStereoFrame f =
            sim.Run(path.At(t), aar_description::DefaultBoomPose(), 1000 + i, true, true);
        const auto& k = w.rig.intrinsics;
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
      std::printf("%-24s %9ld %10.4f %8.4f %11.2f %9ld %10.4f %8ld\n", v.name, stats.n,
                  stats.mean(), stats.sd(), -100.0 * z * z / fB * stats.mean(), all.n, all.mean(),
                  outline);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_disparity: %s\n", e.what());
    return 1;
  }
  return 0;
}
