#include "line_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "aar_alignment/search.h"

namespace aar_alignment::line_model {
namespace {

constexpr int kRingSamples = 4000;    // background pixels read around the receiver per view
constexpr int kMinRingSamples = 200;  // fewer: the receiver fills the image

float Bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const uint8_t* r0 = image.ptr<uint8_t>(y0);
  const uint8_t* r1 = image.ptr<uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

// The probability that the pixel z [px] outward of the predicted outline is the receiver.
float Expected(const Line& l, double z) {
  const std::vector<float>& expected = *l.expected;
  const int half = static_cast<int>(expected.size() / 2);
  const int i = static_cast<int>(std::floor(z)) + half;
  return expected[std::clamp(i, 0, 2 * half - 1)];
}

// Log-likelihood of each hypothesis from the receiver probabilities (LineModel::kRegion): each is
// judged on the window around it only, so that other parts of the receiver further along the
// line do not spoil it.
std::vector<double> RegionLikelihood(const LineShape& shape, const Line& l) {
  std::vector<double> logp(shape.hypotheses, 0.0);
  for (int j = 0; j < shape.hypotheses; ++j) {
    const double d = shape.D(j);
    for (int i = 0; i < shape.pixels; ++i) {
      const double z = shape.X(i) - d;
      if (std::abs(z) > shape.window) continue;
      const double h = Expected(l, z);
      logp[j] += std::log(h * l.foreground[i] + (1.0 - h) * (1.0 - l.foreground[i]));
    }
  }
  return logp;
}

// Log-likelihood of each hypothesis from the grey values alone (LineModel::kContrast): the line's
// pixels split into receiver and background by the shifted profile, each class its own mean grey
// with Gaussian noise of a common variance (profile likelihood -n/2 log(SSE / n)). Every
// hypothesis is judged on all the line's pixels, so that a uniform stretch cannot win by itself.
std::vector<double> ContrastLikelihood(const LineShape& shape, const Line& l) {
  constexpr double kNoiseFloor = 4.0;  // [grey^2] per pixel: uniform sky is not infinitely sure
  constexpr int kFar = std::numeric_limits<int>::max() / 4;
  const std::vector<float>& expected = *l.expected;
  const int last = static_cast<int>(expected.size()) - 1;
  // The receiver's runs [a, b) of profile indices; a run at either end reaches on (the profile
  // is read clamped to its ends).
  std::vector<std::pair<int, int>> runs;
  for (int k = 0; k <= last; ++k) {
    if (!(expected[k] > 0.5f)) continue;
    int b = k;
    while (b <= last && expected[b] > 0.5f) ++b;
    runs.emplace_back(k == 0 ? -kFar : k, b > last ? kFar : b);
    k = b;
  }
  // Prefix sums of the grey values and their squares along the line.
  const int pixels = shape.pixels;
  std::vector<double> sum_to(pixels + 1, 0.0), square_to(pixels + 1, 0.0);
  for (int i = 0; i < pixels; ++i) {
    const float g = l.grey[i];
    sum_to[i + 1] = sum_to[i] + g;
    square_to[i + 1] = square_to[i] + g * g;
  }
  const double all = sum_to[pixels], all_square = square_to[pixels], n = pixels;
  std::vector<double> logp(shape.hypotheses, 0.0);
  for (int j = 0; j < shape.hypotheses; ++j) {
    // Pixel i lies at x = i - pixels / 2 + 1/2: its profile index for the outline at D(j).
    const int shift = (last + 1) / 2 - pixels / 2 - static_cast<int>(std::lround(shape.D(j)));
    double count = 0.0, sum = 0.0, square = 0.0;  // of the receiver's class
    for (const auto& [a, b] : runs) {
      const int from = std::max(a - shift, 0), to = std::min(b - shift, pixels);
      if (from >= to) continue;
      count += to - from;
      sum += sum_to[to] - sum_to[from];
      square += square_to[to] - square_to[from];
    }
    double sse = 0.0;
    if (count > 0.0) sse += square - sum * sum / count;
    if (n - count > 0.0) sse += (all_square - square) - (all - sum) * (all - sum) / (n - count);
    logp[j] = -0.5 * n * std::log(sse / n + kNoiseFloor);
  }
  return logp;
}

}  // namespace

// Reads a line's grey values, one per pixel along it; kUnseen outside the image or on the boom.
void Sample(const View& v, const LineShape& shape, Line& line) {
  line.grey.assign(static_cast<size_t>(shape.pixels), kUnseen);
  const int w = v.image->cols, h = v.image->rows;
  const bool boom = !v.boom.empty();
  for (int i = 0; i < shape.pixels; ++i) {
    const Eigen::Vector2d p = line.center + shape.X(i) * line.normal;
    if (!(p.x() >= 0.0 && p.y() >= 0.0 && p.x() < w - 1 && p.y() < h - 1)) continue;
    if (boom && v.boom.at<uint8_t>(static_cast<int>(p.y() + 0.5), static_cast<int>(p.x() + 0.5)))
      continue;
    line.grey[i] = Bilinear(*v.image, p.x(), p.y());
  }
}

// The smoothed profile (Line::expected): the profile averaged over `radius` px either side, as
// probabilities 1/2 -+ amplitude (SRT3D's smoothed step); beyond the profile, background.
std::vector<float> Smoothed(const std::vector<uint8_t>& profile, int radius, double amplitude) {
  const int n = static_cast<int>(profile.size());
  std::vector<int> sum(n + 1, 0);
  for (int i = 0; i < n; ++i) sum[i + 1] = sum[i] + profile[i];
  std::vector<float> out(n);
  for (int i = 0; i < n; ++i) {
    const int a = std::max(0, i - radius), b = std::min(n, i + radius + 1);
    const double share = static_cast<double>(sum[b] - sum[a]) / (2 * radius + 1);
    out[i] = static_cast<float>(0.5 + amplitude * (2.0 * share - 1.0));
  }
  return out;
}

// The grey statistics of one view: the ring around the receiver against the lines' pixels
// (GreyPosterior::FromNeighbourhood); where the receiver fills the image and leaves no ring,
// the lines' pixels that the predicted outline gives the receiver against the others.
GreyPosterior Posterior(const View& v, const std::vector<Line>& lines, int view,
                        const std::vector<ContourPoint>& contour, const LineShape& shape,
                        int bins) {
  Eigen::AlignedBox2d box;
  for (const ContourPoint& c : contour) box.extend(c.pixel);
  const std::vector<float> ring = RingSamples(
      *v.image, v.boom, box, std::max(24.0, 0.1 * box.sizes().maxCoeff()), kRingSamples);
  std::vector<float> near, receiver, background;
  for (const Line& l : lines) {
    if (l.view != view) continue;
    for (int i = 0; i < shape.pixels; ++i) {
      if (l.grey[i] == kUnseen) continue;
      near.push_back(l.grey[i]);
      if (std::abs(shape.X(i)) <= shape.window)
        (Expected(l, shape.X(i)) > 0.5 ? receiver : background).push_back(l.grey[i]);
    }
  }
  if (static_cast<int>(ring.size()) >= kMinRingSamples)
    return GreyPosterior::FromNeighbourhood(ring, near, bins);
  return GreyPosterior::FromLabels(receiver, background, bins);
}

// The distribution of the outline's place along the line (mean, variance, fit). As
// SRT3D, a line with any pixel unseen (outside the image, on the boom) is not used: an unseen
// pixel favours the hypotheses whose window it lies in.
void Distribution(const LineShape& shape, LineModel model, const GreyPosterior& posterior,
                  Line& l) {
  l.usable = std::find(l.grey.begin(), l.grey.end(), kUnseen) == l.grey.end();
  if (!l.usable) return;
  if (model == LineModel::kRegion) {
    l.foreground.resize(shape.pixels);
    for (int i = 0; i < shape.pixels; ++i) l.foreground[i] = posterior(l.grey[i]);
  }
  const std::vector<double> logp =
      model == LineModel::kContrast ? ContrastLikelihood(shape, l) : RegionLikelihood(shape, l);
  const double top = *std::max_element(logp.begin(), logp.end());
  double sum = 0.0, mean = 0.0, square = 0.0;
  for (int j = 0; j < shape.hypotheses; ++j) {
    const double p = std::exp(logp[j] - top), d = shape.D(j);
    sum += p, mean += p * d, square += p * d * d;
  }
  l.mean = mean / sum;
  l.variance = std::max(square / sum - l.mean * l.mean, shape.spacing * shape.spacing / 12.0);
  // The fit: how much more the distribution puts within kInlierPx of the predicted outline than
  // a line without any edge would (a flat distribution), in [0, 1].
  double near = 0.0;
  int near_hypotheses = 0;
  for (int j = 0; j < shape.hypotheses; ++j) {
    if (std::abs(shape.D(j)) > kInlierPx) continue;
    near += std::exp(logp[j] - top) / sum;
    ++near_hypotheses;
  }
  const double flat = static_cast<double>(near_hypotheses) / shape.hypotheses;
  l.fit = std::max(0.0, (near - flat) / (1.0 - flat));
}

}  // namespace aar_alignment::line_model
