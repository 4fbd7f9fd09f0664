#include "aar_sim/sensor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace aar_sim {
namespace {

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

// One stream per (seed, view, effect): reproducible whatever order views are rendered in. Salt 0
// is the read noise's stream, the one the renderer drew before the sensor model existed.
std::mt19937_64 NoiseStream(uint64_t seed, uint64_t view_key, uint64_t salt) {
  return std::mt19937_64((seed * 0x9E3779B97F4A7C15ull ^ (view_key + 1) * 0xD1B54A32D192ED03ull) ^
                         salt);
}
constexpr uint64_t kShotNoiseSalt = 0x5851F42D4C957F2Dull;

// Bilinear sample at (x, y) [px], clamped to the image.
float Sample(const Image<float>& image, float x, float y) {
  x = std::clamp(x, 0.0f, static_cast<float>(image.width - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(image.height - 1));
  const int u = std::min(static_cast<int>(x), image.width - 2 < 0 ? 0 : image.width - 2);
  const int v = std::min(static_cast<int>(y), image.height - 2 < 0 ? 0 : image.height - 2);
  const int u1 = std::min(u + 1, image.width - 1), v1 = std::min(v + 1, image.height - 1);
  const float fx = x - u, fy = y - v;
  const float top = image.at(u, v) + fx * (image.at(u1, v) - image.at(u, v));
  const float bottom = image.at(u, v1) + fx * (image.at(u1, v1) - image.at(u, v1));
  return top + fy * (bottom - top);
}

// Distance [m] from p to the box (0 inside).
double BoxDistance(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  return (box.min() - p).cwiseMax(p - box.max()).cwiseMax(0.0).norm();
}

// Motion blur's steps (MotionBlur below).

// A pixel whose body moves it by (dx, dy) [px] over the exposure.
struct MovingPixel {
  int u, v;
  float dx, dy;
};

struct PixelBox {
  int u_min, u_max, v_min, v_max;  // inclusive
};

// The moving pixels and the box they cover during the exposure (it may leave the image).
struct MovingPixels {
  std::vector<MovingPixel> pixels;
  PixelBox reach;
};

// Of the bodies with a pixel's label, the one nearest to its point p (optical frame).
const BodyMotion* NearestBody(const std::vector<const BodyMotion*>& candidates,
                              const Eigen::Vector3d& p) {
  const BodyMotion* body = candidates.front();
  if (candidates.size() > 1) {
    double best = std::numeric_limits<double>::infinity();
    for (const BodyMotion* b : candidates) {
      const double d = BoxDistance(b->box_in_body, b->T_body_optical * p);
      if (d < best) best = d, body = b;
    }
  }
  return body;
}

// Each pixel's image motion d over the exposure [px]: back-projected with its depth, moved with
// its body (the nearest one of its label), projected again. Background and unmoved bodies: 0.
MovingPixels FindMovingPixels(const Image<uint8_t>& label, const Image<float>& depth,
                              const ViewMotion& motion) {
  const int w = depth.width, h = depth.height;
  const CameraIntrinsics& k = motion.intrinsics;
  std::array<std::vector<const BodyMotion*>, 256> bodies_of;  // by label value
  for (const auto& [body_label, body] : motion.bodies)
    bodies_of[static_cast<uint8_t>(body_label)].push_back(&body);
  MovingPixels moving;
  moving.reach = {w, -1, h, -1};
  auto& r = moving.reach;
  for (int v = 0; v < h; ++v) {
    const float* z_row = &depth.at(0, v);
    const uint8_t* label_row = &label.at(0, v);
    for (int u = 0; u < w; ++u) {
      const float z = z_row[u];
      if (!(z > 0.0f)) continue;
      const std::vector<const BodyMotion*>& candidates = bodies_of[label_row[u]];
      if (candidates.empty()) continue;
      const Eigen::Vector3d p(z * (u - k.cx) / k.fx, z * (v - k.cy) / k.fy, z);
      const Eigen::Vector3d q = NearestBody(candidates, p)->T_end_start * p;
      if (!(q.z() > 0.0)) continue;
      const Eigen::Vector2d d = k.Project(q) - Eigen::Vector2d(u, v);
      if (d.squaredNorm() < 1e-6) continue;  // below a thousandth of a pixel: still
      moving.pixels.push_back({u, v, static_cast<float>(d.x()), static_cast<float>(d.y())});
      r.u_min = std::min(r.u_min, u + static_cast<int>(std::floor(std::min(0.0, d.x()))));
      r.u_max = std::max(r.u_max, u + static_cast<int>(std::ceil(std::max(0.0, d.x()))));
      r.v_min = std::min(r.v_min, v + static_cast<int>(std::floor(std::min(0.0, d.y()))));
      r.v_max = std::max(r.v_max, v + static_cast<int>(std::ceil(std::max(0.0, d.y()))));
    }
  }
  return moving;
}

// Leading edges' coverage, kept only over the moving pixels' reach (clipped to the image): per
// pixel, the fraction of the exposure a moving body covers it and that body's radiance times it.
struct BlurCoverage {
  BlurCoverage(const PixelBox& reach, int w, int h)
      : u_min(std::max(reach.u_min, 0)),
        u_max(std::min(reach.u_max, w - 1)),
        v_min(std::max(reach.v_min, 0)),
        v_max(std::min(reach.v_max, h - 1)),
        box_w(u_max - u_min + 1),
        box_h(v_max - v_min + 1),
        coverage(static_cast<size_t>(box_w) * box_h, 0.0f),
        covered(coverage.size(), 0.0f) {}
  size_t Index(int u, int v) const { return static_cast<size_t>(v - v_min) * box_w + (u - u_min); }

  int u_min, u_max, v_min, v_max, box_w, box_h;
  std::vector<float> coverage, covered;
};

// Trailing edges and interiors (gather): a pixel that a point of its body crosses during the
// exposure shows what was at q - s d at the start, for s over the exposure; beyond the trailing
// edge that is the background next to it (what the body uncovers is not rendered). Returns each
// moving pixel's gathered radiance.
// Leading edges (scatter): a body covers the pixels in front of it, nearer than what they show,
// for part of the exposure; each covering tap adds 1/taps of coverage and of its radiance.
std::vector<float> GatherAndScatter(const Image<float>& radiance, const Image<uint8_t>& label,
                                    const Image<float>& depth, const MovingPixels& moving,
                                    BlurCoverage* cover) {
  const int w = radiance.width;
  std::vector<float> gathered(moving.pixels.size());
  constexpr int kMaxTaps = 16;
  constexpr float kShift = 4096.0f;  // rounds by truncation: u + s d is above -kShift
  for (size_t m = 0; m < moving.pixels.size(); ++m) {
    const MovingPixel& p = moving.pixels[m];
    const size_t index = static_cast<size_t>(p.v) * w + p.u;
    const float length = std::hypot(p.dx, p.dy);
    const int taps = std::clamp(static_cast<int>(std::ceil(length)) + 1, 2, kMaxTaps);
    const float r0 = radiance.data[index], z0 = depth.data[index], weight = 1.0f / taps;
    const uint8_t l0 = label.data[index];
    float sum = 0.0f;
    for (int i = 0; i < taps; ++i) {
      const float s = (i + 0.5f) * weight;  // mid-interval taps over the exposure
      sum += Sample(radiance, p.u - s * p.dx, p.v - s * p.dy);
      const int qu = static_cast<int>(p.u + s * p.dx + 0.5f + kShift) - static_cast<int>(kShift),
                qv = static_cast<int>(p.v + s * p.dy + 0.5f + kShift) - static_cast<int>(kShift);
      if (qu < cover->u_min || qv < cover->v_min || qu > cover->u_max || qv > cover->v_max)
        continue;
      const size_t q = static_cast<size_t>(qv) * w + qu;
      const float zq = depth.data[q];
      if (label.data[q] == l0 || (zq > 0.0f && zq <= z0)) continue;  // own body, or in front
      const size_t b = cover->Index(qu, qv);
      cover->coverage[b] += weight;
      cover->covered[b] += r0 * weight;
    }
    gathered[m] = sum * weight;
  }
  return gathered;
}

// The leading edges over the gathered image, by their coverage (at most the whole exposure).
void BlendLeadingEdges(const BlurCoverage& cover, Image<float>* out) {
  for (int v = cover.v_min; v <= cover.v_max; ++v) {
    for (int u = cover.u_min; u <= cover.u_max; ++u) {
      const size_t b = cover.Index(u, v);
      if (cover.coverage[b] <= 0.0f) continue;
      const float c = std::min(cover.coverage[b], 1.0f);
      out->at(u, v) = (1.0f - c) * out->at(u, v) + c * cover.covered[b] / cover.coverage[b];
    }
  }
}

}  // namespace

void SensorOptions::Validate() const {
  auto check = [](bool ok, const std::string& field, const std::string& rule) {
    if (!ok) throw std::invalid_argument("sensor option " + field + " " + rule);
  };
  check(noise_stddev >= 0.0, "noise_stddev", "must not be negative");
  check(full_well >= 0.0, "full_well", "must not be negative (0: no shot noise)");
  check(exposure_time > 0.0 && exposure_time <= 1.0, "exposure_time",
        "must be in (0, 1] s: an exposure of zero or less is not an exposure");
  check(gain_mismatch > -0.5 && gain_mismatch < 0.5, "gain_mismatch", "must be in (-0.5, 0.5)");
  check(exposure_target > 0.0 && exposure_target < 255.0, "exposure_target",
        "must be in (0, 255) grey levels");
  check(exposure_gain_min > 0.0, "exposure_gain_min", "must be positive");
  check(exposure_gain_max >= exposure_gain_min, "exposure_gain_max",
        "must not be below exposure_gain_min");
}

uint8_t ToUnorm8(float r) {
  r = r > 0.0f ? std::min(r, 1.0f) : 0.0f;  // NaN to 0
  // Mesa's lp_build_clamped_float_to_unsigned_norm: r * 255/256 + 2^15 leaves the rounded value
  // (to nearest, ties to even) in the low 8 bits of the mantissa.
  const float t = r * (255.0f / 256.0f) + 32768.0f;
  uint32_t bits;
  std::memcpy(&bits, &t, sizeof(bits));
  return static_cast<uint8_t>(bits & 0xffu);
}

double ExposureGain(const SensorOptions& options, const Image<float>& radiance) {
  if (!options.auto_exposure) return 1.0;
  // Centre-weighted metering: the central half of each axis, where the receiver and the boom are
  // while the pipeline tracks them, every other pixel and row (a metering grid).
  std::vector<float> metered;
  metered.reserve(static_cast<size_t>(radiance.width / 4 + 1) * (radiance.height / 4 + 1));
  for (int v = radiance.height / 4; v < radiance.height - radiance.height / 4; v += 2)
    for (int u = radiance.width / 4; u < radiance.width - radiance.width / 4; u += 2)
      metered.push_back(std::max(radiance.at(u, v), 0.0f));
  if (metered.empty()) return 1.0;
  // The scale at which the image's metered mean, clipped at white, is the target: where a
  // camera's exposure loop settles (solved per frame, so without its lag).
  const double target = options.exposure_target / 255.0;
  auto mean_at = [&](double gain) {
    double sum = 0.0;
    for (float r : metered) sum += std::min(gain * r, 1.0);
    return sum / metered.size();
  };
  double sum = 0.0;
  float brightest = 0.0f;
  for (float r : metered) sum += r, brightest = std::max(brightest, r);
  double lo = options.exposure_gain_min, hi = options.exposure_gain_max;
  if (!(sum > 0.0)) return hi;
  // Highlights first: at most 1 % of the metered pixels may clip, as a camera's exposure control
  // protects them; else a lit receiver over dark ground turns white and loses its texture.
  std::vector<float> order = metered;
  const auto p99 = order.begin() + static_cast<std::ptrdiff_t>(0.99 * (order.size() - 1));
  std::nth_element(order.begin(), p99, order.end());
  if (*p99 > 0.0f) hi = std::clamp(1.0 / *p99, lo, hi);
  const double unclipped = std::clamp(target * metered.size() / sum, lo, hi);
  if (unclipped * brightest <= 1.0) return unclipped;  // nothing clips: the plain ratio
  if (mean_at(hi) <= target) return hi;
  if (mean_at(lo) >= target) return lo;
  for (int i = 0; i < 40 && hi - lo > 1e-6 * hi; ++i) {  // the clipped mean grows with the gain
    const double mid = 0.5 * (lo + hi);
    (mean_at(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

Image<float> MotionBlur(const Image<float>& radiance, const Image<uint8_t>& label,
                        const Image<float>& depth, const ViewMotion& motion) {
  const int w = radiance.width, h = radiance.height;
  if (label.width != w || label.height != h || depth.width != w || depth.height != h) {
    throw std::invalid_argument("motion blur needs the label and depth of the view (" +
                                std::to_string(w) + "x" + std::to_string(h) + ")");
  }
  if (motion.bodies.empty()) return radiance;
  const MovingPixels moving = FindMovingPixels(label, depth, motion);
  Image<float> out = radiance;
  if (moving.pixels.empty()) return out;
  BlurCoverage coverage(moving.reach, w, h);
  const std::vector<float> gathered = GatherAndScatter(radiance, label, depth, moving, &coverage);
  for (size_t m = 0; m < moving.pixels.size(); ++m)
    out.at(moving.pixels[m].u, moving.pixels[m].v) = gathered[m];
  BlendLeadingEdges(coverage, &out);
  return out;
}

Image<uint8_t> Expose(const SensorOptions& options, const SensorInput& input) {
  if (!input.radiance) throw std::invalid_argument("the sensor needs the view's radiance");
  const Image<float>* radiance = input.radiance;
  Image<float> blurred;
  if (options.motion_blur && input.motion) {
    if (!input.label || !input.depth) {
      throw std::invalid_argument("motion blur needs the view's label and depth");
    }
    blurred = MotionBlur(*radiance, *input.label, *input.depth, *input.motion);
    radiance = &blurred;
  }
  const float gain = static_cast<float>(input.exposure_gain *
                                        (input.camera == 1 ? 1.0 + options.gain_mismatch : 1.0));
  Image<uint8_t> image;
  image.width = radiance->width;
  image.height = radiance->height;
  image.data.resize(radiance->data.size());
  const float* r = radiance->data.data();
  const std::vector<float>& normal = NormalTable();
  if (options.full_well > 0.0) {
    // Shot noise: e = s * full_well electrons (s = gained radiance, 1 = a full well), Poisson,
    // approximated by a Gaussian of variance e: in radiance units, s / full_well. A saturated
    // pixel (s >= 1) stays saturated.
    std::mt19937_64 rng = NoiseStream(options.noise_seed, input.view_key, kShotNoiseSalt);
    const float per_electron = static_cast<float>(1.0 / options.full_well);
    uint64_t bits = 0;
    for (size_t i = 0; i < image.data.size(); ++i) {
      if (i % 4 == 0) bits = rng();
      float s = r[i] * gain;
      if (s > 0.0f && s < 1.0f)
        s += std::sqrt(s * per_electron) * normal[(bits >> (16 * (i % 4))) & 0xffffu];
      image.data[i] = ToUnorm8(s);
    }
  } else if (gain == 1.0f) {
    for (size_t i = 0; i < image.data.size(); ++i) image.data[i] = ToUnorm8(r[i]);
  } else {
    for (size_t i = 0; i < image.data.size(); ++i) image.data[i] = ToUnorm8(r[i] * gain);
  }
  if (options.noise_stddev > 0.0) {
    // Read noise on the quantised value, as the renderer added it before the sensor model existed
    // (the same stream, so images with read noise alone stay bit-identical).
    std::mt19937_64 rng = NoiseStream(options.noise_seed, input.view_key, 0);
    const float sigma = static_cast<float>(options.noise_stddev);
    uint64_t bits = 0;
    for (size_t i = 0; i < image.data.size(); ++i) {
      if (i % 4 == 0) bits = rng();
      const float v = image.data[i] + sigma * normal[(bits >> (16 * (i % 4))) & 0xffffu];
      // std::clamp(std::lround(v), 0, 255) as before, without the library call: v + 0.5 is exact
      // in double, and truncation is floor for what is positive.
      image.data[i] =
          v > 0.0f
              ? static_cast<uint8_t>(std::min(static_cast<int>(static_cast<double>(v) + 0.5), 255))
              : 0;
    }
  }
  return image;
}

}  // namespace aar_sim
