#include "aar_alignment/statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace aar_alignment {
namespace {

constexpr double kFloor = 1e-3;  // a grey never seen is not impossible

std::vector<double> Histogram(const std::vector<float>& grey, int bins) {
  std::vector<double> h(bins, 0.0);
  for (const float g : grey) h[std::min(bins - 1, static_cast<int>(g * bins / 256.0f))] += 1.0;
  const double n = std::accumulate(h.begin(), h.end(), 0.0);
  if (n > 0.0)
    for (double& v : h) v /= n;
  return h;
}

}  // namespace

GreyPosterior GreyPosterior::FromLabels(const std::vector<float>& receiver,
                                        const std::vector<float>& background, int bins) {
  const std::vector<double> f = Histogram(receiver, bins), g = Histogram(background, bins);
  GreyPosterior out;
  out.p_.resize(bins);
  for (int b = 0; b < bins; ++b)
    out.p_[b] = static_cast<float>(
        std::clamp((f[b] + kFloor) / (f[b] + g[b] + 2 * kFloor), 1e-3, 1.0 - 1e-3));
  return out;
}

GreyPosterior GreyPosterior::FromNeighbourhood(const std::vector<float>& background,
                                               const std::vector<float>& neighbourhood, int bins) {
  const std::vector<double> near = Histogram(neighbourhood, bins), bg = Histogram(background, bins);
  double share = 1.0;  // of the background in the neighbourhood
  for (int b = 0; b < bins; ++b)
    if (bg[b] > 0.01) share = std::min(share, near[b] / bg[b]);
  std::vector<double> fg(bins);
  for (int b = 0; b < bins; ++b) fg[b] = std::max(0.0, near[b] - share * bg[b]);
  const double n = std::accumulate(fg.begin(), fg.end(), 0.0);
  GreyPosterior out;
  out.p_.resize(bins);
  for (int b = 0; b < bins; ++b) {
    const double f = (n > 0.0 ? fg[b] / n : 0.0) + kFloor, g = bg[b] + kFloor;
    out.p_[b] = static_cast<float>(std::clamp(f / (f + g), 1e-3, 1.0 - 1e-3));
  }
  return out;
}

std::vector<float> RingSamples(const cv::Mat& image, const cv::Mat& boom,
                               const Eigen::AlignedBox2d& box, double gap, int count) {
  if (box.isEmpty()) return {};
  const Eigen::Vector2d g = Eigen::Vector2d::Constant(gap);
  const Eigen::Vector2d reach =
      g + Eigen::Vector2d::Constant(std::max(32.0, 0.5 * box.sizes().maxCoeff()));
  const Eigen::AlignedBox2d inner(box.min() - g, box.max() + g);
  Eigen::AlignedBox2d outer(box.min() - reach, box.max() + reach);
  outer = outer.intersection(Eigen::AlignedBox2d(Eigen::Vector2d::Zero(),
                                                 Eigen::Vector2d(image.cols - 1, image.rows - 1)));
  if (outer.isEmpty()) return {};
  const double area = outer.volume() - inner.intersection(outer).volume();
  if (area <= 0.0) return {};
  const int stride = std::max(1, static_cast<int>(std::sqrt(area / count)));
  std::vector<float> grey;
  for (int y = static_cast<int>(std::ceil(outer.min().y())); y <= outer.max().y(); y += stride) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    for (int x = static_cast<int>(std::ceil(outer.min().x())); x <= outer.max().x(); x += stride) {
      if (inner.contains(Eigen::Vector2d(x, y))) continue;
      if (!boom.empty() && boom.at<uint8_t>(y, x)) continue;
      grey.push_back(row[x]);
    }
  }
  return grey;
}

}  // namespace aar_alignment
