#include "aar_alignment/acquire.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "aar_alignment/boom_parts.h"
#include "aar_alignment/search.h"

namespace aar_alignment {
namespace {

struct Placement {
  double score = 0.0;  // the search's
  double fit = 0.0;    // the outline's there (OutlineAligner::Score)
  double range = 0.0;  // [m] along the axis of the camera it was found in
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  const PinholeCamera* camera = nullptr;  // the camera whose image it was found in
};

// The receiver at `attitude`, `range` [m] along the camera's ray through `pixel`.
Eigen::Isometry3d AtPixel(const PinholeCamera& c, const Eigen::Matrix3d& attitude, double range,
                          const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d optical(pixel.x() - c.cx, pixel.y() - c.cy, 0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = attitude;
  T.translation() = c.T_tanker_optical *
                    Eigen::Vector3d(optical.x() * range / c.fx, optical.y() * range / c.fy, range);
  return T;
}

// The prior of an alignment from `p`: `along` [m] along its camera's ray to it, `across` [m]
// across it, `rotation` [rad].
Matrix6d PlacementCovariance(const Placement& p, double along, double across, double rotation) {
  const Eigen::Vector3d u =
      (p.T_tanker_receiver.translation() - p.camera->T_tanker_optical.translation()).normalized();
  Matrix6d covariance = Matrix6d::Zero();
  covariance.topLeftCorner<3, 3>() = across * across * Eigen::Matrix3d::Identity() +
                                     (along * along - across * across) * u * u.transpose();
  covariance.bottomRightCorner<3, 3>() = rotation * rotation * Eigen::Matrix3d::Identity();
  return covariance;
}

// Whether enough of the outline is seen at an alignment or a placement (AcquisitionOptions::
// min_visible).
bool Seen(const AcquisitionOptions& o, const AlignmentResult& r) {
  return r.valid && SeenShare(o, r) >= o.min_visible;
}

// Where stereo's cue puts the receiver in `camera`'s image, and how far.
struct Cue {
  Eigen::Vector2d pixel;  // [px] the group's median
  double depth = 0.0;     // [m] the group's median along the camera's axis
};

double Median(std::vector<double>& x) {
  std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
  return x[x.size() / 2];
}

// Of the cue's points between min_range and max_range in front of `camera` and inside its image,
// the most that lie within the receiver's radius (`radius_m` at the point's depth) of one of them:
// their median pixel and depth; none when fewer than cue_min_points lie so together (or the cue
// is off). Points scattered over the image (mismatches where the boom hides the receiver from one
// camera) cue nothing.
std::optional<Cue> StereoCue(const PinholeCamera& camera, const AcquisitionOptions& o,
                             const std::vector<Eigen::Vector3d>& cue, double radius_m) {
  if (o.cue_min_points <= 0) return std::nullopt;
  const Eigen::Isometry3d T_optical_tanker = camera.T_tanker_optical.inverse();
  std::vector<Eigen::Vector4d> pixels;  // u, v [px], the radius there [px], depth [m]
  for (const Eigen::Vector3d& p : cue) {
    const Eigen::Vector3d y = T_optical_tanker * p;
    if (!(y.z() >= o.min_range && y.z() <= o.max_range)) continue;
    const Eigen::Vector2d px = camera.Project(y);
    if (px.x() < 0.0 || px.y() < 0.0 || px.x() > camera.width - 1 || px.y() > camera.height - 1)
      continue;
    pixels.emplace_back(px.x(), px.y(), camera.fx * radius_m / y.z(), y.z());
  }
  std::vector<double> best_u, best_v, best_z;
  for (const Eigen::Vector4d& centre : pixels) {
    std::vector<double> u, v, z;
    for (const Eigen::Vector4d& p : pixels) {
      if ((p.head<2>() - centre.head<2>()).norm() > centre.z()) continue;
      u.push_back(p.x()), v.push_back(p.y()), z.push_back(p.w());
    }
    if (u.size() > best_u.size()) best_u.swap(u), best_v.swap(v), best_z.swap(z);
  }
  if (static_cast<int>(best_u.size()) < o.cue_min_points) return std::nullopt;
  return Cue{Eigen::Vector2d(Median(best_u), Median(best_v)), Median(best_z)};
}

// Whether `range` is searched under `cue` (AcquisitionOptions::cue_disparity_margin_px): its
// disparity within the margin of the cue's, at the rig's `baseline_m`.
bool InCuesRange(const PinholeCamera& camera, const AcquisitionOptions& o,
                 const std::optional<Cue>& cue, double baseline_m, double range) {
  if (!cue || !(o.cue_disparity_margin_px > 0.0)) return true;
  const double fb = camera.fx * baseline_m;
  return std::abs(fb / range - fb / cue->depth) <= o.cue_disparity_margin_px;
}

// The search over the image of `camera` (`image`, `boom` its mask) at every range: the
// placements seen, into `placements`; returns the ranges whose search found one.
int SearchRanges(const OutlineAligner& aligner, const AlignmentInput& in, const cv::Mat& image,
                 const PinholeCamera& camera, const AcquisitionOptions& o,
                 const std::vector<Eigen::Vector3d>& cue, std::vector<Placement>& placements) {
  const cv::Mat boom = BoomMask(camera, in.boom_parts_in_tanker, aligner.options().boom_margin_px);
  const double radius_m = aligner.model().radius();
  const std::optional<Cue> cued = StereoCue(camera, o, cue, radius_m);
  const Eigen::Vector2d centre =
      cued ? cued->pixel : Eigen::Vector2d(0.5 * (camera.width - 1), 0.5 * (camera.height - 1));
  const double baseline_m = (in.right_camera.T_tanker_optical.translation() -
                             in.left_camera.T_tanker_optical.translation())
                                .norm();
  ShiftSearchOptions search;
  search.template_size = o.template_size;
  search.uniform_scores_zero = true;
  int ranges = 0;
  for (double range = o.min_range; range <= o.max_range * (1.0 + 1e-9); range *= o.range_step) {
    if (!InCuesRange(camera, o, cued, baseline_m, range)) continue;
    search.radius_px = cued ? camera.fx * radius_m / range + o.cue_margin_px
                            : 0.5 * std::max(camera.width, camera.height) + 1.0;  // whole image
    const ShiftSearchResult s = SearchShift(
        aligner.model(), image, boom, camera,
        AtPixel(camera, in.T_tanker_receiver_predicted.linear(), range, centre), search);
    if (!s.valid) continue;
    ++ranges;
    AlignmentInput a = in;
    a.T_tanker_receiver_predicted = s.T_tanker_receiver;
    const AlignmentResult fit = aligner.Score(a);
    if (Seen(o, fit))
      placements.push_back({s.score, fit.quality, range, s.T_tanker_receiver, &camera});
  }
  return ranges;
}

// The images searched, as (image, camera): the first rig's left and every further rig's left
// (extra views 0, 2, ...); with both_views every image, each rig's left before its right.
std::vector<std::pair<const cv::Mat*, const PinholeCamera*>> Searched(const AlignmentInput& in,
                                                                      bool both_views) {
  std::vector<std::pair<const cv::Mat*, const PinholeCamera*>> images = {
      {&in.left, &in.left_camera}};
  if (both_views) images.push_back({&in.right, &in.right_camera});
  for (size_t i = 0; i < in.extra_views.size(); ++i)
    if (both_views || i % 2 == 0)
      images.push_back({&in.extra_views[i].image, &in.extra_views[i].camera});
  return images;
}

// The images searched, in words (an error's).
std::string SearchedWords(const AlignmentInput& in, bool both_views) {
  if (in.extra_views.empty()) return both_views ? "either image" : "the left image";
  return both_views ? "any image" : "any rig's left image";
}

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

double SeenShare(const AcquisitionOptions& o, const AlignmentResult& r) {
  auto share = [](int lines, int outline) {
    return outline > 0 ? static_cast<double>(lines) / outline : 0.0;
  };
  const size_t views = std::min(r.view_lines.size(), r.view_outline_lines.size());
  // One rig (or no views): both views' lines together, as the totals count them.
  if (!o.both_views && views <= 2) return share(r.lines, r.outline_lines);
  double best = 0.0;
  const size_t step = o.both_views ? 1 : 2;  // per view, or per rig (its left and right)
  for (size_t v = 0; v + step <= views; v += step) {
    const int lines = o.both_views ? r.view_lines[v] : r.view_lines[v] + r.view_lines[v + 1];
    const int outline = o.both_views ? r.view_outline_lines[v]
                                     : r.view_outline_lines[v] + r.view_outline_lines[v + 1];
    best = std::max(best, share(lines, outline));
  }
  return best;
}

void AcquisitionOptions::Validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("acquisition: " + what); };
  if (!(min_range > 0.0) || !(max_range >= min_range))
    fail("min_range must be > 0 and max_range >= min_range");
  if (!(range_step > 1.0)) fail("range_step must be > 1");
  if (template_size < 8) fail("template_size must be at least 8 px");
  if (candidates < 1) fail("candidates must be at least 1");
  if (cue_min_points < 0) fail("cue_min_points must be >= 0");
  if (!(cue_margin_px >= 0.0)) fail("cue_margin_px must be >= 0");
  if (!(cue_disparity_margin_px >= 0.0)) fail("cue_disparity_margin_px must be >= 0");
  if (!(min_visible >= 0.0 && min_visible <= 1.0)) fail("min_visible must lie in [0, 1]");
  if (!(sigma_across > 0.0) || !(sigma_rotation > 0.0))
    fail("sigma_across and sigma_rotation must be > 0");
}

AcquisitionResult Acquire(const OutlineAligner& aligner, const AlignmentInput& in,
                          const AcquisitionOptions& o, const std::vector<Eigen::Vector3d>& cue) {
  const auto start = std::chrono::steady_clock::now();
  AcquisitionResult out;
  out.error = CheckAlignmentInput(in);
  if (!out.error.empty()) return out;
  std::vector<Placement> placements;
  for (const auto& [image, camera] : Searched(in, o.both_views))
    out.ranges += SearchRanges(aligner, in, *image, *camera, o, cue, placements);
  if (placements.empty()) {
    out.error =
        out.ranges == 0
            ? "the silhouette fits " + SearchedWords(in, o.both_views) +
                  " at none of the ranges searched"
            : "where the silhouette fits best, less than min_visible of its outline is seen";
    out.time_ms = MsSince(start);
    return out;
  }
  // The search finds where the receiver lies in the image at every range alike; the outline's fit
  // there tells the ranges apart (the search's score grows as the silhouette shrinks).
  std::sort(placements.begin(), placements.end(),
            [](const Placement& a, const Placement& b) { return a.fit > b.fit; });
  placements.resize(std::min<size_t>(placements.size(), o.candidates));
  for (const Placement& p : placements) {
    AlignmentInput a = in;
    a.T_tanker_receiver_predicted = p.T_tanker_receiver;
    a.prediction_covariance =
        PlacementCovariance(p, p.range * (o.range_step - 1.0), o.sigma_across, o.sigma_rotation);
    const AlignmentResult r = aligner.Align(a);
    ++out.aligned;
    if (!Seen(o, r)) {
      if (out.error.empty())
        out.error = r.valid ? "aligned, less than min_visible of the outline is seen" : r.error;
      continue;
    }
    if (out.valid && r.quality <= out.alignment.quality) continue;
    out.valid = true;
    out.alignment = r;
    out.range_m = p.range;
    out.search_score = p.score;
  }
  if (out.valid) out.error.clear();
  out.time_ms = MsSince(start);
  return out;
}

}  // namespace aar_alignment
