#include "aar_sim/raw_camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <aar_geometry/pose.h>

namespace aar_sim {

RawCameraOptions DefaultRawCameraOptions() {
  RawCameraOptions o;
  // Barrel distortion of a ~6 mm C-mount lens on a 1/1.8" sensor (60 deg HFOV): k1 -0.2 to -0.3
  // with a smaller positive k2; the two lenses differ a little, as two real ones do.
  o.left.distortion = {-0.26, 0.09, 0.0006, -0.0004, -0.012};
  o.right.distortion = {-0.24, 0.08, -0.0005, 0.0003, -0.010};
  // A few tenths of a degree: what stereoRectify's R1, R2 hold for a carefully mounted pair.
  o.left.rotation_deg = {0.15, -0.30, 0.10};
  o.right.rotation_deg = {-0.20, 0.25, -0.15};
  return o;
}

namespace {

Eigen::Matrix3d RotationFromVectorDeg(const Eigen::Vector3d& r_deg) {
  const double angle = aar_geometry::DegToRad(r_deg.norm());
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, r_deg.normalized()).toRotationMatrix();
}

}  // namespace

RawCamera::RawCamera(const CameraIntrinsics& rectified, const LensOptions& lens)
    : k_(rectified), lens_(lens), R_rect_raw_(RotationFromVectorDeg(lens.rotation_deg)) {
  for (double d : lens.distortion) {
    if (!std::isfinite(d)) throw std::invalid_argument("lens distortion must be finite");
  }
  if (!lens.rotation_deg.allFinite()) throw std::invalid_argument("lens rotation must be finite");
  const cv::Matx33d K(k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1);
  const cv::Matx33d P = K;  // the rectified projection's left 3x3 (Tx plays no part in a map)
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = R_rect_raw_(i, j);
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(lens_.distortion.data()));

  // Every raw pixel through undistortPoints (iterated to convergence: the default 5 iterations
  // leave tenths of a pixel at the corners of a 10 % barrel).
  std::vector<cv::Point2f> raw, rect;
  raw.reserve(static_cast<size_t>(k_.width) * k_.height);
  for (int v = 0; v < k_.height; ++v)
    for (int u = 0; u < k_.width; ++u)
      raw.emplace_back(static_cast<float>(u), static_cast<float>(v));
  cv::undistortPoints(
      raw, rect, K, D, R, P,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  map_x_.create(k_.height, k_.width, CV_32F);
  map_y_.create(k_.height, k_.width, CV_32F);
  size_t outside = 0;
  float beyond_x = 0.0f, beyond_y = 0.0f;  // [px] farthest beyond the view's edges
  for (int v = 0, i = 0; v < k_.height; ++v) {
    for (int u = 0; u < k_.width; ++u, ++i) {
      const cv::Point2f& p = rect[static_cast<size_t>(i)];
      map_x_.at<float>(v, u) = p.x;
      map_y_.at<float>(v, u) = p.y;
      outside += !(p.x >= 0.0f && p.x <= k_.width - 1 && p.y >= 0.0f && p.y <= k_.height - 1);
      beyond_x = std::max({beyond_x, -p.x, p.x - (k_.width - 1)});
      beyond_y = std::max({beyond_y, -p.y, p.y - (k_.height - 1)});
    }
  }
  outside_fraction_ = static_cast<double>(outside) / rect.size();
  if (!(beyond_x < k_.width && beyond_y < k_.height))
    throw std::invalid_argument(
        "lens distortion makes the raw camera see more than three times "
        "the rectified view: not a lens a calibration would give");
  margin_x_ = beyond_x > 0.0f ? static_cast<int>(std::ceil(beyond_x)) + 2 : 0;
  margin_y_ = beyond_y > 0.0f ? static_cast<int>(std::ceil(beyond_y)) + 2 : 0;
  // A lens folding back on itself (strong pincushion, k1 far too large) is no calibration.
  const int vc = k_.height / 2, uc = k_.width / 2;
  for (int u = 1; u < k_.width; ++u) {
    if (!(map_x_.at<float>(vc, u) > map_x_.at<float>(vc, u - 1)))
      throw std::invalid_argument("lens distortion folds the image's centre row back at column " +
                                  std::to_string(u) + ": not a lens a calibration would give");
  }
  for (int v = 1; v < k_.height; ++v) {
    if (!(map_y_.at<float>(v, uc) > map_y_.at<float>(v - 1, uc)))
      throw std::invalid_argument("lens distortion folds the image's centre column back at row " +
                                  std::to_string(v) + ": not a lens a calibration would give");
  }
  SetViewMargin(0, 0);
}

void RawCamera::SetViewMargin(int mx, int my) {
  if (mx < 0 || my < 0) throw std::invalid_argument("RawCamera: view margins must not be negative");
  view_mx_ = mx;
  view_my_ = my;
  cv::Mat x = map_x_ + static_cast<float>(mx), y = map_y_ + static_cast<float>(my);
  cv::convertMaps(x, y, fixed1_, fixed2_, CV_16SC2);
}

Image<uint8_t> RawCamera::Distort(const Image<uint8_t>& view) const {
  const int w = k_.width + 2 * view_mx_, h = k_.height + 2 * view_my_;
  if (view.width != w || view.height != h ||
      view.data.size() != static_cast<size_t>(view.width) * view.height)
    throw std::invalid_argument("RawCamera::Distort: view is " + std::to_string(view.width) + "x" +
                                std::to_string(view.height) + ", expected " + std::to_string(w) +
                                "x" + std::to_string(h) + " (camera and view margins)");
  const cv::Mat in(h, w, CV_8UC1, const_cast<uint8_t*>(view.data.data()));
  Image<uint8_t> out;
  out.width = k_.width;
  out.height = k_.height;
  out.data.resize(static_cast<size_t>(k_.width) * k_.height);
  cv::Mat dst(k_.height, k_.width, CV_8UC1, out.data.data());
  cv::remap(in, dst, fixed1_, fixed2_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

Eigen::Vector2d RawCamera::RectifiedPixel(double u, double v) const {
  const cv::Matx33d K(k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1);
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = R_rect_raw_(i, j);
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(lens_.distortion.data()));
  std::vector<cv::Point2d> raw{{u, v}}, rect;
  cv::undistortPoints(
      raw, rect, K, D, R, K,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  return {rect[0].x, rect[0].y};
}

}  // namespace aar_sim
