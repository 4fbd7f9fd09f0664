#pragma once

#include <array>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_sim/camera.h"
#include "aar_sim/renderer.h"

namespace aar_sim {

// One camera as a stereo calibration (camera_calibration, OpenCV's stereoRectify) describes it:
// a lens with plumb_bob distortion, turned slightly away from the ideal rectified camera.
struct LensOptions {
  std::array<double, 5> distortion{};  // plumb_bob k1, k2, p1, p2, k3 (CameraInfo D)
  // R_rect_raw (CameraInfo R: raw camera frame into the rectified one) as a rotation vector in
  // the optical frame (x right, y down, z forward) [deg]: axis times angle.
  Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();
};

// Raw (distorted, unrectified) output of the stereo pair. Off: the rectified pinhole images.
struct RawCameraOptions {
  bool enabled = false;
  LensOptions left, right;
};

// The realistic defaults documented in config/sim.yaml: a ~60 deg HFOV machine-vision lens
// (barrel, about 10 % at the image corners) and a few tenths of a degree of rotation per camera.
RawCameraOptions DefaultRawCameraOptions();

// Turns the ideal rectified view of one camera into the image the real camera would deliver:
// raw pixel (u, v) shows what the rectified image shows at cv::undistortPoints((u, v), K, D, R,
// P), exactly the inverse of image_proc's rectification (cv::initUndistortRectifyMap with the
// same K, D, R, P). K, the raw camera's intrinsics, equals the rectified ones (fx, fy, cx, cy).
class RawCamera {
 public:
  // Throws std::invalid_argument for non-finite values or a distortion so strong that the
  // image's centre row is no longer monotonic (not a lens a calibration would accept).
  RawCamera(const CameraIntrinsics& rectified, const LensOptions& lens);

  // How far [px] beyond the rectified view's edges the raw camera looks (a barrel lens's edges
  // and corners), with 2 px to spare for interpolation: the margins of the view to render.
  int margin_x() const { return margin_x_; }
  int margin_y() const { return margin_y_; }
  // The rectified view that Distort takes is `mx`, `my` [px] larger on each side than the
  // camera's (same fx, fy; principal point moved by mx, my). Default 0: the camera's own size.
  void SetViewMargin(int mx, int my);

  // The raw image from the rectified view (camera size plus the view margins). Raw pixels that
  // look beyond the view repeat its nearest edge pixel (none do with margins >= margin_x/y()).
  Image<uint8_t> Distort(const Image<uint8_t>& view) const;
  // Where raw pixel (u, v) [px] lies in the rectified image [px] (the map Distort uses).
  Eigen::Vector2d RectifiedPixel(double u, double v) const;

  const CameraIntrinsics& K() const { return k_; }
  const std::array<double, 5>& D() const { return lens_.distortion; }
  const Eigen::Matrix3d& R_rect_raw() const { return R_rect_raw_; }
  // The fraction of raw pixels that see beyond the rectified view (edge pixels repeated).
  double outside_fraction() const { return outside_fraction_; }
  const CameraIntrinsics& rectified() const { return k_; }

 private:
  CameraIntrinsics k_;
  LensOptions lens_;
  Eigen::Matrix3d R_rect_raw_;
  cv::Mat map_x_, map_y_;    // CV_32F: rectified position of each raw pixel
  cv::Mat fixed1_, fixed2_;  // the same with the view margins, as fixed-point maps (speed)
  double outside_fraction_ = 0.0;
  int margin_x_ = 0, margin_y_ = 0;
  int view_mx_ = 0, view_my_ = 0;
};

}  // namespace aar_sim
