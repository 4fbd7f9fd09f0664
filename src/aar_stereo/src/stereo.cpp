#include "aar_stereo/stereo.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace aar_stereo {
namespace {

using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

void Check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// Grey level at row-major pixel index `px`; rows may be padded (step > width).
float Grey(const cv::Mat& image, int px) {
  return image.ptr<uint8_t>(px / image.cols)[px % image.cols];
}

SparseMatchOptions ToSparseOptions(const StereoOptions& o);

}  // namespace

void StereoOptions::Validate() const {
  Check(block_size % 2 == 1 && block_size >= (matcher != Matcher::kSemiGlobal ? 5 : 1) &&
            block_size <= 255,
        "block_size must be odd, 5..255 for block matching (1..255 semi-global), not " +
            std::to_string(block_size));
  Check(
      num_disparities > 0 && num_disparities % 16 == 0,
      "num_disparities must be a positive multiple of 16, not " + std::to_string(num_disparities));
  Check(prefilter_size % 2 == 1 && prefilter_size >= 5 && prefilter_size <= 255,
        "prefilter_size must be odd, 5..255, not " + std::to_string(prefilter_size));
  Check(prefilter_cap >= 1 && prefilter_cap <= 63, "prefilter_cap must be 1..63");
  Check(texture_threshold >= 0, "texture_threshold must not be negative");
  Check(uniqueness_ratio >= 0, "uniqueness_ratio must not be negative");
  Check(speckle_window_size >= 0 && speckle_range >= 0, "speckle settings must not be negative");
  Check(median_filter == 0 || median_filter == 3 || median_filter == 5,
        "median_filter must be 0 (off), 3 or 5, not " + std::to_string(median_filter));
  Check(max_range > 0.0, "max_range must be positive");
  Check(decimation != Decimation::kEveryNth || keep_every >= 1, "keep_every must be at least 1");
  Check(decimation != Decimation::kVoxelGrid || voxel_size > 0.0, "voxel_size must be positive");
  Check(!organized || decimation == Decimation::kNone, "an organized cloud needs decimation none");
  if (matcher == Matcher::kSparse) {
    Check(median_filter == 0, "median_filter needs a dense matcher, not sparse");
    ToSparseOptions(*this).Validate();
  }
}

StereoGeometry StereoGeometry::Rectified(int width, int height, double fx, double fy, double cx,
                                         double cy, double baseline) {
  StereoGeometry g;
  g.width = width;
  g.height = height;
  g.fx = fx;
  g.fy = fy;
  g.cx_left = g.cx_right = cx;
  g.cy = cy;
  g.Tx = -fx * baseline;
  return g;
}

cv::Matx44d StereoGeometry::Q() const {
  // Disparities are pre-adjusted by (cx_left - cx_right), as stereo_image_proc does, so the
  // principal points' difference does not appear here.
  const double b = baseline();
  return cv::Matx44d(1.0, 0.0, 0.0, -cx_left,           //
                     0.0, fx / fy, 0.0, -cy * fx / fy,  //
                     0.0, 0.0, 0.0, fx,                 //
                     0.0, 0.0, 1.0 / b, 0.0);
}

void StereoGeometry::Validate() const {
  Check(width > 0 && height > 0, "camera info has no image size");
  Check(fx > 0.0 && fy > 0.0,
        "camera info projection matrix P has no focal length (P[0] or P[5] is 0)");
  Check(std::isfinite(cx_left) && std::isfinite(cy) && std::isfinite(cx_right) && std::isfinite(Tx),
        "camera info projection matrix P is not finite");
  Check(Tx < 0.0, "right camera info P[3] (-fx * baseline) must be negative, is " +
                      std::to_string(Tx) + ": not the right camera of a rectified pair");
}

cv::Rect ProjectedRoi(const std::vector<Eigen::Vector3d>& points, const StereoGeometry& g,
                      int margin) {
  const cv::Rect full(0, 0, g.width, g.height);
  double u0 = 1e18, u1 = -1e18, v0 = 1e18, v1 = -1e18;
  for (const auto& p : points) {
    if (!(p.z() > 0.0)) return full;  // behind the camera: its projection is unbounded
    const double u = g.fx * p.x() / p.z() + g.cx_left, v = g.fy * p.y() / p.z() + g.cy;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  if (points.empty()) return full;
  const auto clamp = [](double x, int hi) {
    return static_cast<int>(std::clamp(x, -1.0, static_cast<double>(hi + 1)));
  };
  const int x0 = clamp(std::floor(u0) - margin, g.width),
            x1 = clamp(std::ceil(u1) + margin + 1, g.width);
  const int y0 = clamp(std::floor(v0) - margin, g.height),
            y1 = clamp(std::ceil(v1) + margin + 1, g.height);
  return cv::Rect(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)) & full;
}

int MaxDisparity(const std::vector<Eigen::Vector3d>& points, const StereoGeometry& g) {
  double z_min = 1e18;
  for (const auto& p : points) z_min = std::min(z_min, p.z());
  if (!(z_min > 0.0)) return std::numeric_limits<int>::max();
  return static_cast<int>(std::ceil(g.fx * g.baseline() / z_min + (g.cx_left - g.cx_right))) + 1;
}

std::vector<Eigen::Vector3d> BoxCorners(const Eigen::AlignedBox3d& box,
                                        const Eigen::Isometry3d& T_optical_body, double grow) {
  Eigen::AlignedBox3d grown = box;
  grown.min().array() -= grow;
  grown.max().array() += grow;
  std::vector<Eigen::Vector3d> corners;
  for (int c = 0; c < 8; ++c)
    corners.push_back(T_optical_body *
                      grown.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  return corners;
}

StereoProcessor::StereoProcessor(const StereoOptions& options) : options_(options) {
  options_.Validate();
}

namespace {

void CheckImages(const cv::Mat& left, const cv::Mat& right, const StereoGeometry& geometry) {
  Check(!left.empty() && !right.empty(), "empty image");
  Check(left.type() == CV_8UC1 && right.type() == CV_8UC1,
        "images must be 8-bit single channel (mono8)");
  Check(left.size() == right.size(),
        "left image is " + std::to_string(left.cols) + "x" + std::to_string(left.rows) +
            ", right " + std::to_string(right.cols) + "x" + std::to_string(right.rows));
  geometry.Validate();
  Check(left.cols == geometry.width && left.rows == geometry.height,
        "images are " + std::to_string(left.cols) + "x" + std::to_string(left.rows) +
            ", camera info says " + std::to_string(geometry.width) + "x" +
            std::to_string(geometry.height));
}

// The matcher's window for a region of interest: widened so that the matcher sees the right
// image's candidates (to the left by the disparity range) and the block's margins.
cv::Rect MatchWindow(const cv::Rect& roi, const cv::Rect& full, const StereoOptions& o) {
  if (roi.area() == 0) return cv::Rect();  // nothing predicted in view: nothing to match
  if (roi == full) return full;
  const int margin = o.block_size / 2 + 1;
  cv::Rect match = cv::Rect(roi.x - o.min_disparity - o.num_disparities - margin, roi.y - margin,
                            roi.width + o.num_disparities + o.min_disparity + 2 * margin,
                            roi.height + 2 * margin) &
                   full;
  // OpenCV refuses images smaller than the block: grow a window clipped at a corner.
  if (match.width < o.block_size)
    match.x = std::max(0, std::min(match.x, full.width - o.block_size)), match.width = o.block_size;
  if (match.height < o.block_size)
    match.y = std::max(0, std::min(match.y, full.height - o.block_size)),
    match.height = o.block_size;
  return match & full;
}

cv::Mat DenseDisparity16(const cv::Mat& left, const cv::Mat& right, const StereoOptions& o) {
  cv::Mat disparity16;
  if (o.matcher != Matcher::kSemiGlobal) {  // block matching (kSparse: frames without a roi)
    auto bm = cv::StereoBM::create(o.num_disparities, o.block_size);
    bm->setMinDisparity(o.min_disparity);
    bm->setPreFilterSize(o.prefilter_size);
    bm->setPreFilterCap(o.prefilter_cap);
    bm->setTextureThreshold(o.texture_threshold);
    bm->setUniquenessRatio(o.uniqueness_ratio);
    bm->setSpeckleWindowSize(o.speckle_window_size);
    bm->setSpeckleRange(o.speckle_range);
    bm->setDisp12MaxDiff(o.disp12_max_diff);
    bm->compute(left, right, disparity16);
  } else {
    const int area = o.block_size * o.block_size;
    auto sgbm = cv::StereoSGBM::create(
        o.min_disparity, o.num_disparities, o.block_size, o.sgbm_p1 > 0 ? o.sgbm_p1 : 8 * area,
        o.sgbm_p2 > 0 ? o.sgbm_p2 : 32 * area, o.disp12_max_diff, o.prefilter_cap,
        o.uniqueness_ratio, o.speckle_window_size, o.speckle_range,
        o.sgbm_full_dp ? cv::StereoSGBM::MODE_HH : cv::StereoSGBM::MODE_SGBM);
    sgbm->compute(left, right, disparity16);
  }
  return disparity16;
}

SparseMatchOptions ToSparseOptions(const StereoOptions& o) {
  SparseMatchOptions s;
  s.block_size = o.block_size;
  s.min_disparity = o.min_disparity;
  s.num_disparities = o.num_disparities;
  s.prefilter_cap = o.prefilter_cap;
  s.texture_threshold = o.texture_threshold;
  s.uniqueness_ratio = o.uniqueness_ratio;
  s.lr_max_diff = o.sparse_lr_max_diff;
  s.budget = o.sparse_budget;
  return s;
}

// Reprojection of the matched pixels (row-major indices): [x y z w] = Q [u v d 1], by hand
// (cv::reprojectImageTo3D's arithmetic); disparities at or below 0 (infinity) and points beyond
// max_range are left out.
void Reproject(const cv::Mat& disparity, const std::vector<int>& pixels, const cv::Matx44d& Q,
               double max_range, std::vector<Eigen::Vector3f>* points,
               std::vector<int>* pixel_of_point) {
  points->reserve(pixels.size());
  for (int px : pixels) {
    const int v = px / disparity.cols, u = px % disparity.cols;
    const double d = disparity.ptr<float>(v)[u];
    if (d <= 0.0) continue;
    const double w = Q(3, 2) * d + Q(3, 3);
    const Eigen::Vector3f p(static_cast<float>((u * Q(0, 0) + Q(0, 3)) / w),
                            static_cast<float>((v * Q(1, 1) + Q(1, 3)) / w),
                            static_cast<float>(Q(2, 3) / w));
    if (!(p.z() <= max_range)) continue;
    points->push_back(p);
    pixel_of_point->push_back(px);
  }
}

}  // namespace

void StereoProcessor::MatchDense(const cv::Mat& left, const cv::Mat& right, const cv::Rect& roi,
                                 float shift, StereoResult* result) const {
  const StereoOptions& o = options_;
  const cv::Rect match = MatchWindow(roi, cv::Rect(0, 0, left.cols, left.rows), o);
  if (match.area() == 0) return;
  const cv::Mat disparity16 = DenseDisparity16(left(match), right(match), o);
  // Fixed point (1/16 px) to float, adjusted for the principal points as stereo_image_proc does.
  const int invalid16 = (o.min_disparity - 1) * 16;
  for (int v = roi.y; v < roi.y + roi.height; ++v) {
    const short* src = disparity16.ptr<short>(v - match.y);
    float* dst = result->disparity.ptr<float>(v);
    for (int u = roi.x; u < roi.x + roi.width; ++u) {
      const short d = src[u - match.x];
      if (d > invalid16) dst[u] = d / 16.0f - shift;
    }
  }
  if (o.median_filter > 0 && roi.area() > 0) {
    const float invalid = static_cast<float>(o.min_disparity - 1);
    const cv::Mat region = result->disparity(roi);
    cv::Mat filtered;
    cv::medianBlur(region, filtered, o.median_filter);
    // Where nothing matched nothing is made up; a median of mostly unmatched pixels is unmatched.
    filtered.setTo(invalid, region <= invalid);
    filtered.copyTo(region);
  }
}

std::vector<int> StereoProcessor::MatchAtSamples(const cv::Mat& left, const cv::Mat& right,
                                                 const cv::Rect& roi,
                                                 const std::vector<DisparityZone>& zones,
                                                 float shift, StereoResult* result) const {
  SparseMatches m = MatchSparse(left, right, roi, zones, ToSparseOptions(options_));
  for (size_t i = 0; i < m.pixel.size(); ++i)
    result->disparity.ptr<float>(m.pixel[i] / left.cols)[m.pixel[i] % left.cols] =
        m.disparity16[i] / 16.0f - shift;
  std::vector<int> pixels = std::move(m.pixel);
  m.disparity16.clear();
  result->sparse = true;
  result->samples = std::move(m);
  return pixels;
}

StereoResult StereoProcessor::Process(const cv::Mat& left, const cv::Mat& right,
                                      const StereoGeometry& geometry,
                                      const std::optional<cv::Rect>& roi_in,
                                      const std::vector<DisparityZone>& zones) const {
  const auto t0 = Clock::now();
  CheckImages(left, right, geometry);
  const StereoOptions& o = options_;
  const cv::Rect full(0, 0, left.cols, left.rows);
  const cv::Rect roi = roi_in ? (*roi_in & full) : full;
  const float invalid = static_cast<float>(o.min_disparity - 1);
  const float shift = static_cast<float>(geometry.cx_left - geometry.cx_right);
  StereoResult result;
  result.disparity = cv::Mat(left.size(), CV_32F, cv::Scalar(invalid));
  // Columns the search range cannot reach and the block's margins never get a disparity.
  result.valid_window =
      cv::getValidDisparityROI(full, full, o.min_disparity, o.num_disparities, o.block_size) & roi;
  std::vector<int> pixels;  // the matched pixels, row-major
  if (o.matcher == Matcher::kSparse && roi_in) {
    pixels = MatchAtSamples(left, right, roi, zones, shift, &result);
  } else {
    MatchDense(left, right, roi, shift, &result);
    for (int v = roi.y; v < roi.y + roi.height; ++v) {
      const float* d_row = result.disparity.ptr<float>(v);
      for (int u = roi.x; u < roi.x + roi.width; ++u)
        if (d_row[u] > invalid) pixels.push_back(v * left.cols + u);
    }
  }
  const auto t1 = Clock::now();

  std::vector<Eigen::Vector3f> points;
  std::vector<int> pixel_of_point;
  Reproject(result.disparity, pixels, geometry.Q(), o.max_range, &points, &pixel_of_point);
  result.valid_pixels = static_cast<int>(points.size());
  const auto t2 = Clock::now();
  Decimate(left, points, pixel_of_point, result.sparse, &result.cloud);
  const auto t3 = Clock::now();
  result.timings = {Ms(t0, t1), Ms(t1, t2), Ms(t2, t3), Ms(t0, t3)};
  return result;
}

void StereoProcessor::Decimate(const cv::Mat& left, const std::vector<Eigen::Vector3f>& points,
                               const std::vector<int>& pixel_of_point, bool sparse,
                               CloudPoints* out) const {
  const StereoOptions& o = options_;
  CloudPoints& cloud = *out;
  auto add = [&](size_t i) {
    cloud.xyz.push_back(points[i]);
    cloud.pixel.push_back(pixel_of_point[i]);
    if (o.intensity) cloud.intensity.push_back(Grey(left, pixel_of_point[i]));
  };
  if (o.decimation == Decimation::kNone && o.organized) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    cloud.xyz.assign(static_cast<size_t>(left.rows) * left.cols, Eigen::Vector3f(nan, nan, nan));
    cloud.pixel.assign(cloud.xyz.size(), -1);
    if (o.intensity) cloud.intensity.assign(cloud.xyz.size(), 0.0f);
    for (size_t i = 0; i < points.size(); ++i) {
      cloud.xyz[pixel_of_point[i]] = points[i];
      cloud.pixel[pixel_of_point[i]] = pixel_of_point[i];
      if (o.intensity) cloud.intensity[pixel_of_point[i]] = Grey(left, pixel_of_point[i]);
    }
    cloud.width = left.cols;
    cloud.height = left.rows;
    return;
  }
  if (o.decimation == Decimation::kVoxelGrid) {
    VoxelGrid(left, points, pixel_of_point, &cloud);
  } else {
    const size_t step =
        o.decimation == Decimation::kEveryNth && !sparse ? static_cast<size_t>(o.keep_every) : 1;
    for (size_t i = 0; i < points.size(); i += step) add(i);
  }
  cloud.width = static_cast<int>(cloud.xyz.size());
  cloud.height = 1;
}

void StereoProcessor::VoxelGrid(const cv::Mat& left, const std::vector<Eigen::Vector3f>& points,
                                const std::vector<int>& pixel_of_point, CloudPoints* out) const {
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double intensity = 0;
    int n = 0;
    size_t order;
  };
  std::unordered_map<int64_t, Cell> cells;
  const double inv = 1.0 / options_.voxel_size;
  for (size_t i = 0; i < points.size(); ++i) {
    const int64_t x = static_cast<int64_t>(std::floor(points[i].x() * inv)) & 0x1fffff;
    const int64_t y = static_cast<int64_t>(std::floor(points[i].y() * inv)) & 0x1fffff;
    const int64_t z = static_cast<int64_t>(std::floor(points[i].z() * inv)) & 0x1fffff;
    auto [it, inserted] = cells.try_emplace((x << 42) | (y << 21) | z);
    if (inserted) it->second.order = i;
    it->second.sum += points[i].cast<double>();
    it->second.intensity += Grey(left, pixel_of_point[i]);
    ++it->second.n;
  }
  std::vector<const Cell*> ordered;  // first-seen order: deterministic output
  ordered.reserve(cells.size());
  for (const auto& [key, cell] : cells) ordered.push_back(&cell);
  std::sort(ordered.begin(), ordered.end(),
            [](const Cell* a, const Cell* b) { return a->order < b->order; });
  for (const Cell* c : ordered) {
    out->xyz.push_back((c->sum / c->n).cast<float>());
    out->pixel.push_back(pixel_of_point[c->order]);
    if (options_.intensity) out->intensity.push_back(static_cast<float>(c->intensity / c->n));
  }
}

}  // namespace aar_stereo
