// The sensor model (sensor.h): the ideal sensor gives what the renderer's 8-bit attachment gave
// before it existed, and each effect does what docs/realism/sensor.md says it models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include <opencv2/imgproc.hpp>

#include <aar_description/boom_model.h>
#include <aar_geometry/pose.h>
#include <ros/package.h>

#include "aar_sim/sensor.h"
#include "aar_sim/world.h"

namespace aar_sim {

using aar_description::DefaultBoomPose;
namespace {

WorldOptions TestWorld(int width, int height) {
  WorldOptions o = DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
  o.rig = MakeStereoRig(CameraIntrinsics::FromHorizontalFov(width, height, 60.0), 0.5);
  return o;
}

FlightPathRow Receiver(double x, double y, double z) {
  FlightPathRow row;
  row.position_m = {x, y, z};
  row.rpy = {0.0, aar_geometry::DegToRad(-2.0), aar_geometry::DegToRad(3.0)};
  return row;
}

Image<float> Flat(int width, int height, float value) {
  Image<float> image;
  image.width = width;
  image.height = height;
  image.data.assign(static_cast<size_t>(width) * height, value);
  return image;
}

// Mean and variance of the grey levels.
std::pair<double, double> Moments(const std::vector<uint8_t>& data) {
  double sum = 0.0, sum2 = 0.0;
  for (uint8_t v : data) sum += v, sum2 += double(v) * v;
  const double mean = sum / data.size();
  return {mean, sum2 / data.size() - mean * mean};
}

// Mean grey level over the central half of each axis (where auto-exposure meters).
double CentralMean(const Image<uint8_t>& image) {
  double sum = 0.0;
  int n = 0;
  for (int v = image.height / 4; v < image.height - image.height / 4; ++v)
    for (int u = image.width / 4; u < image.width - image.width / 4; ++u)
      sum += image.at(u, v), ++n;
  return sum / n;
}

// The renderer's read noise before the sensor model existed (renderer.cpp at e0e349f, verbatim):
// the reference for images with noise.
// Inverse of the standard normal CDF (Acklam's rational approximation, relative error < 1.2e-9).
double NormalQuantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (p < 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - 0.02425) return -NormalQuantile(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

// Standard normal samples indexed by 16 random bits: 65536 equiprobable quantiles (tails cut at
// 4.3 sigma). Four pixels per 64-bit draw; Box-Muller per pixel cost 45 ms a 1280x960 view.
const std::vector<float>& NormalTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(65536);
    for (size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<float>(NormalQuantile((i + 0.5) / 65536.0));
    return t;
  }();
  return table;
}

std::vector<uint8_t> MainsNoise(std::vector<uint8_t> image, double noise_stddev,
                                uint64_t noise_seed, uint64_t view_key) {
  std::mt19937_64 rng(noise_seed * 0x9E3779B97F4A7C15ull ^ (view_key + 1) * 0xD1B54A32D192ED03ull);
  const std::vector<float>& normal = NormalTable();
  const float sigma = static_cast<float>(noise_stddev);
  uint64_t bits = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    if (i % 4 == 0) bits = rng();
    const float v = image[i] + sigma * normal[(bits >> (16 * (i % 4))) & 0xffffu];
    image[i] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return image;
}

}  // namespace

// The ideal sensor is OpenGL's conversion to an 8-bit attachment, which made the images before
// the sensor model existed: on every float near a rounding tie, and on real frames of the
// approach with and without read noise (the same stream as before).
TEST(Sensor, IdealSensorGivesTheImagesOfTheEightBitAttachment) {
  World world(TestWorld(640, 480));
  // Floats within 40 ulps of each tie (k + 0.5) / 255 and of each level k / 255, and beyond.
  std::vector<float> values = {-1.0f, -0.0f, 0.0f, 1.0f, 1.5f, 1e-30f, 0.99999994f};
  for (int k = 0; k <= 255; ++k) {
    for (const float centre : {(k + 0.5f) / 255.0f, k / 255.0f}) {
      float f = centre;
      for (int i = 0; i < 40; ++i) f = std::nextafter(f, -1.0f);
      for (int i = 0; i < 81; ++i, f = std::nextafter(f, 2.0f)) values.push_back(f);
    }
  }
  Image<float> sweep = Flat(512, (static_cast<int>(values.size()) + 511) / 512, 0.0f);
  std::copy(values.begin(), values.end(), sweep.data.begin());
  SensorInput input;
  input.radiance = &sweep;
  const Image<uint8_t> gl = world.renderer().ConvertLikeR8Attachment(sweep);
  const Image<uint8_t> ideal = Expose(SensorOptions(), input);
  int naive_differs = 0;  // round half away from zero in float, for the record
  for (size_t i = 0; i < values.size(); ++i) {
    ASSERT_EQ(ideal.data[i], gl.data[i]) << "radiance " << values[i];
    naive_differs += gl.data[i] != std::lround(std::clamp(values[i], 0.0f, 1.0f) * 255.0f) ? 1 : 0;
  }
  std::cout << values.size() << " floats near ties, naive rounding differs on " << naive_differs
            << "\n";

  for (const double x : {-150.0, -60.0, -36.0}) {  // far, mid, near contact
    const StereoFrame frame = world.Render(Receiver(x, 1.0, -13.0), DefaultBoomPose(), 5);
    for (const RenderedView* view : {&frame.left, &frame.right}) {
      const Image<uint8_t> reference = world.renderer().ConvertLikeR8Attachment(view->radiance);
      EXPECT_EQ(view->image.data, reference.data) << "x " << x;
    }
  }
  WorldOptions noisy = TestWorld(640, 480);
  noisy.sensor.noise_stddev = 2.0;
  noisy.sensor.noise_seed = 7;
  World noisy_world(noisy);
  const StereoFrame frame = noisy_world.Render(Receiver(-60.0, 1.0, -13.0), DefaultBoomPose(), 5);
  const auto left = noisy_world.renderer().ConvertLikeR8Attachment(frame.left.radiance).data;
  const auto right = noisy_world.renderer().ConvertLikeR8Attachment(frame.right.radiance).data;
  EXPECT_EQ(frame.left.image.data, MainsNoise(left, 2.0, 7, 10));
  EXPECT_EQ(frame.right.image.data, MainsNoise(right, 2.0, 7, 11));
  EXPECT_NE(frame.left.image.data, left);  // the noise is there
}

// Every effect on: the same seed and frame give the same bits, another seed or frame others.
TEST(Sensor, EveryEffectOnIsReproducibleFromTheSeed) {
  WorldOptions o = TestWorld(320, 240);
  o.sensor.noise_stddev = 2.0;
  o.sensor.full_well = 10000.0;
  o.sensor.motion_blur = true;
  o.sensor.exposure_time = 0.01;
  o.sensor.gain_mismatch = 0.03;
  o.sensor.auto_exposure = true;
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0);
  SceneState end{Receiver(-44.9, 1.2, -13.0), DefaultBoomPose()};
  end.boom.pitch += 0.01;
  World world(o);
  const StereoFrame a = world.Render(row, DefaultBoomPose(), 3, false, false, &end);
  const StereoFrame b = World(o).Render(row, DefaultBoomPose(), 3, false, false, &end);
  EXPECT_EQ(a.left.image.data, b.left.image.data);
  EXPECT_EQ(a.right.image.data, b.right.image.data);
  EXPECT_TRUE(a.left.label.data.empty());  // read for the blur, not handed out unasked
  EXPECT_NE(world.Render(row, DefaultBoomPose(), 4, false, false, &end).left.image.data,
            a.left.image.data);
  o.sensor.noise_seed = 2;
  const StereoFrame c = World(o).Render(row, DefaultBoomPose(), 3, false, false, &end);
  EXPECT_NE(c.left.image.data, a.left.image.data);
  EXPECT_NE(c.right.image.data, a.right.image.data);
}

// Shot noise: the variance of a flat patch grows with its signal, 255^2 s / full_well grey
// levels^2 (Poisson in electrons) plus the quantisation's 1/12; none without a full well.
TEST(Sensor, ShotNoiseVarianceGrowsWithTheSignal) {
  SensorOptions o;
  o.full_well = 10000.0;
  for (const float s : {0.05f, 0.2f, 0.5f, 0.8f}) {
    const Image<float> patch = Flat(300, 300, s);
    SensorInput input;
    input.radiance = &patch;
    input.view_key = 9;
    const auto [mean, variance] = Moments(Expose(o, input).data);
    const double modelled = 255.0 * 255.0 * s / o.full_well + 1.0 / 12.0;
    std::cout << "signal " << s << ": mean " << mean << ", variance " << variance << " (model "
              << modelled << ")\n";
    EXPECT_NEAR(mean, 255.0 * s, 0.05) << s;
    EXPECT_NEAR(variance / modelled, 1.0, 0.005) << s;  // measured 0.998 to 1.000
    EXPECT_EQ(Moments(Expose(SensorOptions(), input).data).second, 0.0);
  }
}

// The right camera's gain: its mean over the left's grows by the mismatch.
TEST(Sensor, GainMismatchShowsInTheRightOverLeftMean) {
  WorldOptions o = TestWorld(320, 240);
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0);
  auto ratio = [&](double mismatch) {
    o.sensor.gain_mismatch = mismatch;
    const StereoFrame f = World(o).Render(row, DefaultBoomPose(), 0);
    return Moments(f.right.image.data).first / Moments(f.left.image.data).first;
  };
  const double matched = ratio(0.0), mismatched = ratio(0.03);
  std::cout << "right / left mean: " << matched << " matched, " << mismatched << " mismatched\n";
  EXPECT_NEAR(matched, 1.0, 0.005);  // measured 0.9985 (the two views differ a little)
  EXPECT_NEAR(mismatched / matched, 1.03, 0.001);  // measured 1.02999
}

// Auto-exposure: the same scene under 0.3 and under 1.5 times the light comes out with its central
// mean on the target, both cameras with the left's scale. A lit receiver over a dark sky is kept
// from turning white (at most 1 % of the metered pixels clip); the limits stop the scale.
TEST(Sensor, AutoExposureBringsDarkAndBrightScenesToTheTarget) {
  WorldOptions o = TestWorld(320, 240);
  const FlightPathRow row = Receiver(-45.0, 1.0, -13.0);
  const StereoFrame frame = World(o).Render(row, DefaultBoomPose(), 0);
  SensorOptions automatic;
  automatic.auto_exposure = true;
  automatic.exposure_target = 118.0;
  for (const float light : {0.3f, 1.5f}) {
    Image<float> left = frame.left.radiance, right = frame.right.radiance;
    for (float& r : left.data) r *= light;
    for (float& r : right.data) r *= light;
    SensorInput input;
    input.radiance = &left;
    const double fixed = CentralMean(Expose(SensorOptions(), input));
    input.exposure_gain = ExposureGain(automatic, left);
    const double metered = CentralMean(Expose(automatic, input));
    input.radiance = &right;
    input.camera = 1;
    const double metered_right = CentralMean(Expose(automatic, input));
    std::cout << "light " << light << ": central mean " << fixed << " fixed, " << metered
              << " (right " << metered_right << ") auto-exposed\n";
    EXPECT_GT(std::abs(fixed - 118.0), 20.0) << "light " << light;
    EXPECT_NEAR(metered, 118.0, 0.5) << "light " << light;        // measured 117.73 (both)
    EXPECT_NEAR(metered_right, 118.0, 1.0) << "light " << light;  // measured 117.48 (both)
  }
  o.renderer.sky_level = 30.0;  // in the world, both cameras: the receiver keeps its texture
  o.sensor.auto_exposure = true;
  const StereoFrame dark = World(o).Render(row, DefaultBoomPose(), 0);
  const Image<uint8_t>& image = dark.left.image;
  int white = 0, metered = 0;
  for (int v = image.height / 4; v < image.height - image.height / 4; v += 2)
    for (int u = image.width / 4; u < image.width - image.width / 4; u += 2)
      white += image.at(u, v) == 255, ++metered;
  std::cout << "dark sky: " << white << " of " << metered << " metered pixels white, central mean "
            << CentralMean(image) << "\n";
  EXPECT_LE(white, 0.012 * metered);  // measured 55 of 4800: 1 % above the cap, and ties at it
  EXPECT_GT(CentralMean(image), 30.0 * 1.5);  // brighter than fixed, short of the target
  EXPECT_GT(Moments(dark.right.image.data).first / Moments(dark.left.image.data).first, 0.98);
  automatic.exposure_gain_max = 2.0;
  const Image<float> night = Flat(64, 48, 0.02f);
  EXPECT_DOUBLE_EQ(ExposureGain(automatic, night), 2.0);
  EXPECT_DOUBLE_EQ(ExposureGain(automatic, Flat(64, 48, 1.0f)), 118.0 / 255.0);
  EXPECT_DOUBLE_EQ(ExposureGain(SensorOptions(), night), 1.0);  // off
}

// Motion blur of a dark square moving 5 px right over a bright background: each pixel shows the
// square for the fraction of the exposure it covers it (a ramp 5 px long at both edges).
TEST(Sensor, MotionBlurAveragesAlongTheImageMotion) {
  const int w = 200, h = 100;
  Image<float> radiance = Flat(w, h, 0.8f), depth = Flat(w, h, 0.0f);
  Image<uint8_t> label;
  label.width = w, label.height = h, label.data.assign(w * h, 0);
  for (int v = 30; v < 70; ++v) {
    for (int u = 60; u < 140; ++u) {
      radiance.at(u, v) = 0.2f, depth.at(u, v) = 10.0f;
      label.at(u, v) = static_cast<uint8_t>(Label::kReceiver);
    }
  }
  ViewMotion motion;
  motion.intrinsics = {w, h, 100.0, 100.0, 99.5, 49.5};
  BodyMotion body;
  body.T_end_start = Eigen::Translation3d(0.5, 0.0, 0.0);  // 0.5 m at 10 m: 5 px
  motion.bodies.emplace_back(Label::kReceiver, body);
  const Image<float> blurred = MotionBlur(radiance, label, depth, motion);
  double worst = 0.0;
  for (int u = 50; u < 155; ++u) {
    const double covered =
        std::clamp((u - 59.5) / 5.0, 0.0, 1.0) - std::clamp((u - 139.5) / 5.0, 0.0, 1.0);
    worst = std::max(worst, std::abs(blurred.at(u, 50) - (0.8 - 0.6 * covered)));
  }
  std::cout << "largest difference from the exact blur: " << worst << "\n";
  for (int u = 50; u < 155; ++u) {
    // Covered while 59.5 + 5 s <= u <= 139.5 + 5 s, s in [0, 1].
    const double covered =
        std::clamp((u - 59.5) / 5.0, 0.0, 1.0) - std::clamp((u - 139.5) / 5.0, 0.0, 1.0);
    EXPECT_NEAR(blurred.at(u, 50), 0.8 - 0.6 * covered, 0.045) << "u " << u;  // measured 0.04
  }
  // No motion: nothing changes.
  EXPECT_EQ(MotionBlur(radiance, label, depth, ViewMotion()).data, radiance.data);
  motion.bodies[0].second.T_end_start = Eigen::Isometry3d::Identity();
  EXPECT_EQ(MotionBlur(radiance, label, depth, motion).data, radiance.data);
}

// In the world: a receiver 1 m to the side during the exposure smears its leading edge over the
// sky by its image motion; with the state unchanged at the exposure's end nothing changes.
TEST(Sensor, MotionBlurSmearsTheReceiverByItsImageMotion) {
  WorldOptions o = TestWorld(640, 480);
  o.boom_visible = false;
  o.sensor.motion_blur = true;
  const FlightPathRow row = Receiver(-50.0, 1.0, -13.0);
  const SceneState still{row, DefaultBoomPose()};
  World world(o);
  const StereoFrame sharp = world.Render(row, DefaultBoomPose(), 0, true, true);
  EXPECT_EQ(world.Render(row, DefaultBoomPose(), 0, true, true, &still).left.image.data,
            sharp.left.image.data);
  SceneState moved = still;
  moved.row.position_m.y() += 0.3;  // [m] during the exposure
  const StereoFrame blurred = world.Render(row, DefaultBoomPose(), 0, true, true, &moved);
  const StereoRig& rig = o.rig;
  auto pixel = [&](const FlightPathRow& r) {
    return rig.intrinsics.Project(rig.T_tanker_left_optical.inverse() * r.position_m);
  };
  const Eigen::Vector2d d = pixel(moved.row) - pixel(row);  // [px] image motion
  ASSERT_GT(std::abs(d.x()), 4.0);
  ASSERT_LT(std::abs(d.y()), 0.5);
  // Per row: the sky pixels next to the receiver on its leading side that the blur darkened.
  std::vector<int> runs;
  const int step = d.x() > 0 ? 1 : -1;
  for (int v = 0; v < sharp.left.label.height; ++v) {
    int edge = -1;  // the receiver's last pixel on the leading side
    for (int u = 0; u < sharp.left.label.width; ++u)
      if (sharp.left.label.at(u, v) == static_cast<uint8_t>(Label::kReceiver))
        edge = (edge < 0 || (u - edge) * step > 0) ? u : edge;
    if (edge < 0) continue;
    int run = 0;
    for (int u = edge + step; u >= 0 && u < sharp.left.label.width; u += step, ++run)
      if (sharp.left.label.at(u, v) != 0 ||
          std::abs(blurred.left.image.at(u, v) - sharp.left.image.at(u, v)) < 1)
        break;
    runs.push_back(run);
  }
  ASSERT_GT(runs.size(), 20u);
  std::nth_element(runs.begin(), runs.begin() + runs.size() / 2, runs.end());
  std::cout << "image motion " << d.transpose() << " px, median smear " << runs[runs.size() / 2]
            << " px over " << runs.size() << " rows\n";
  // measured 5 px for 5.29 px (a pixel is darkened while covered at its centre)
  EXPECT_NEAR(runs[runs.size() / 2], std::abs(d.x()), 0.5) << "image motion " << d.x() << " px";
}

// The telescope sliding out during the exposure blurs the telescope and what it passes, never the
// still boom tube around it: each boom pixel moves with the link nearest to its 3-D point.
TEST(Sensor, MotionBlurMovesEachBoomPixelWithItsOwnLink) {
  WorldOptions o = TestWorld(640, 480);
  o.sensor.motion_blur = true;
  const FlightPathRow row = Receiver(-60.0, 1.0, -13.0);
  World world(o);
  const BoomPose start = DefaultBoomPose();
  SceneState end{row, start};
  end.boom.extension += 0.5;  // [m] during the exposure
  const Image<uint8_t> sharp = world.Render(row, start, 0).left.image;
  const Image<uint8_t> sharp_end = world.Render(row, end.boom, 0).left.image;
  const Image<uint8_t> blurred = world.Render(row, start, 0, false, false, &end).left.image;
  // Where the telescope's motion can show: what differs between the two ends, grown by 2 px.
  cv::Mat differs(sharp.height, sharp.width, CV_8UC1), reach;
  for (int v = 0; v < sharp.height; ++v)
    for (int u = 0; u < sharp.width; ++u)
      differs.at<uint8_t>(v, u) = sharp.at(u, v) != sharp_end.at(u, v) ? 255 : 0;
  cv::dilate(differs, reach, cv::Mat(), cv::Point(-1, -1), 2);
  int changed = 0, beyond = 0;
  for (int v = 0; v < sharp.height; ++v) {
    for (int u = 0; u < sharp.width; ++u) {
      if (blurred.at(u, v) == sharp.at(u, v)) continue;
      ++changed;
      beyond += reach.at<uint8_t>(v, u) == 0;
    }
  }
  std::cout << changed << " pixels blurred, " << beyond << " beyond the telescope's reach\n";
  EXPECT_GT(changed, 150);  // measured 173
  EXPECT_EQ(beyond, 0);
}

}  // namespace aar_sim
