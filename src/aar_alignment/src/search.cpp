#include "aar_alignment/search.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <opencv2/imgproc.hpp>

namespace aar_alignment {
namespace {

// Sub-sample position of a maximum from its two neighbours (parabola), in [-0.5, 0.5].
double Vertex(double left, double centre, double right) {
  const double d = left - 2.0 * centre + right;
  return d < 0.0 ? std::clamp(0.5 * (left - right) / d, -0.5, 0.5) : 0.0;
}

// The image around the template's footprint, resampled to the template's scale, with each
// pixel's weight (0 where the boom hides it); none when the receiver leaves the image or fills
// too much of it.
struct SearchWindow {
  cv::Rect roi;    // [px] of the image searched
  cv::Mat grey;    // CV_32F, at the template's scale
  cv::Mat weight;  // CV_32F
};

std::optional<SearchWindow> CutSearchWindow(const SilhouetteMask& mask, const cv::Mat& image,
                                            const cv::Mat& boom, double radius_px) {
  const double m = mask.scale;
  // The template's footprint in the image, and the region searched.
  const Eigen::Vector2d size(mask.image.cols / m, mask.image.rows / m);
  const Eigen::AlignedBox2d footprint(mask.origin, mask.origin + size);
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(radius_px + 1.0 / m) + 0.5 * size;
  SearchWindow w;
  w.roi = cv::Rect(cv::Point(static_cast<int>(std::floor(footprint.min().x() - reach.x())),
                             static_cast<int>(std::floor(footprint.min().y() - reach.y()))),
                   cv::Point(static_cast<int>(std::ceil(footprint.max().x() + reach.x())),
                             static_cast<int>(std::ceil(footprint.max().y() + reach.y())))) &
          cv::Rect(0, 0, image.cols, image.rows);
  // Near contact the receiver fills much of the image: no background around it to search
  // against, and the lines alone reach a tracked receiver's error.
  if (size.x() > image.cols / 3.0 || size.y() > image.rows / 3.0) return std::nullopt;
  if (w.roi.width < size.x() || w.roi.height < size.y()) return std::nullopt;  // leaves the image
  cv::resize(image(w.roi), w.grey, cv::Size(), m, m, cv::INTER_AREA);
  if (w.grey.cols < mask.image.cols || w.grey.rows < mask.image.rows) return std::nullopt;
  w.grey.convertTo(w.grey, CV_32F);
  w.weight = cv::Mat::ones(w.grey.size(), CV_32F);
  if (!boom.empty()) {
    cv::Mat hidden;
    cv::resize(boom(w.roi), hidden, w.grey.size(), 0, 0, cv::INTER_NEAREST);
    w.weight.setTo(0.0f, hidden);
  }
  return w;
}

// Each placement's score: the share of the window's grey variance that the silhouette's split
// into receiver and background explains (R^2 of a two-mean fit), from correlations of the
// weighted grey values. `silhouette`: the mask grown by a margin of background.
cv::Mat TwoMeanScores(const SearchWindow& w, const cv::Mat& silhouette, bool uniform_scores_zero) {
  const cv::Mat box = cv::Mat::ones(silhouette.size(), CV_32F);
  const cv::Mat wi = w.weight.mul(w.grey), wii = wi.mul(w.grey);
  auto correlate = [](const cv::Mat& a, const cv::Mat& t) {
    cv::Mat r;
    cv::matchTemplate(a, t, r, cv::TM_CCORR);
    return r;
  };
  const cv::Mat n_in = correlate(w.weight, silhouette), s_in = correlate(wi, silhouette),
                q_in = correlate(wii, silhouette), n_all = correlate(w.weight, box),
                s_all = correlate(wi, box), q_all = correlate(wii, box);
  // [grey^2] per pixel, added to the whole variance; with uniform_scores_zero to the unexplained
  // as well, so that a uniform window (whose split explains its tiny variance perfectly) scores 0.
  constexpr double kNoiseFloor = 4.0;
  const double template_pixels = cv::sum(silhouette)[0];
  cv::Mat score(n_in.size(), CV_32F);
  for (int y = 0; y < score.rows; ++y) {
    for (int x = 0; x < score.cols; ++x) {
      const double ni = n_in.at<float>(y, x), na = n_all.at<float>(y, x), no = na - ni;
      const double si = s_in.at<float>(y, x), sa = s_all.at<float>(y, x), so = sa - si;
      const double qi = q_in.at<float>(y, x), qa = q_all.at<float>(y, x), qo = qa - qi;
      if (ni < 0.5 * template_pixels || no < 1.0) {
        score.at<float>(y, x) = 0.0f;  // mostly hidden by the boom
        continue;
      }
      const double floor = na * kNoiseFloor;
      const double split =
          (qi - si * si / ni) + (qo - so * so / no) + (uniform_scores_zero ? floor : 0.0);
      const double total = qa - sa * sa / na + floor;
      score.at<float>(y, x) = static_cast<float>(1.0 - split / total);
    }
  }
  return score;
}

}  // namespace

ShiftSearchResult SearchShift(const OutlineModel& model, const cv::Mat& image, const cv::Mat& boom,
                              const PinholeCamera& camera,
                              const Eigen::Isometry3d& T_tanker_receiver,
                              const ShiftSearchOptions& options) {
  ShiftSearchResult out;
  const SilhouetteMask mask =
      model.Silhouette(camera, T_tanker_receiver, options.template_size, 1.0);
  if (mask.image.empty()) return out;
  const double m = mask.scale;
  const std::optional<SearchWindow> window = CutSearchWindow(mask, image, boom, options.radius_px);
  if (!window) return out;
  // Each placement's window is the silhouette's box grown by a margin of background.
  const int margin = std::max(2, mask.image.cols / 4);
  cv::Mat silhouette =
      cv::Mat::zeros(mask.image.rows + 2 * margin, mask.image.cols + 2 * margin, CV_32F);
  mask.image.convertTo(silhouette(cv::Rect(margin, margin, mask.image.cols, mask.image.rows)),
                       CV_32F);
  if (window->grey.cols < silhouette.cols || window->grey.rows < silhouette.rows) return out;
  const cv::Mat score = TwoMeanScores(*window, silhouette, options.uniform_scores_zero);
  // No shift: the template's mask pixel 0 sits on window pixel `offset`.
  const cv::Rect& roi = window->roi;
  const Eigen::Vector2d offset = (mask.origin - Eigen::Vector2d(roi.x, roi.y)) * m +
                                 Eigen::Vector2d::Constant(0.5 * m - 0.5 - margin);
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &at);
  Eigen::Vector2d k(at.x, at.y);
  if (at.x > 0 && at.x + 1 < score.cols)
    k.x() += Vertex(score.at<float>(at.y, at.x - 1), best, score.at<float>(at.y, at.x + 1));
  if (at.y > 0 && at.y + 1 < score.rows)
    k.y() += Vertex(score.at<float>(at.y - 1, at.x), best, score.at<float>(at.y + 1, at.x));
  out.shift_px = (k - offset) / m;
  const cv::Point zero(std::clamp(static_cast<int>(std::lround(offset.x())), 0, score.cols - 1),
                       std::clamp(static_cast<int>(std::lround(offset.y())), 0, score.rows - 1));
  out.score = best;
  out.score_gain = best - score.at<float>(zero);
  // Move the receiver across the line of sight of the camera by the shift.
  const Eigen::Isometry3d T_optical_tanker = camera.T_tanker_optical.inverse();
  Eigen::Vector3d y = T_optical_tanker * T_tanker_receiver.translation();
  y.x() += out.shift_px.x() * y.z() / camera.fx;
  y.y() += out.shift_px.y() * y.z() / camera.fy;
  out.T_tanker_receiver = T_tanker_receiver;
  out.T_tanker_receiver.translation() = camera.T_tanker_optical * y;
  out.valid = true;
  return out;
}

}  // namespace aar_alignment
