#pragma once

#include <Eigen/Geometry>

namespace aar_sim {

// Pinhole intrinsics in OpenCV's convention: pixel (u, v) = (fx X/Z + cx, fy Y/Z + cy) in the
// optical frame, integer values at pixel centres. No distortion.
struct CameraIntrinsics {
  int width = 1280;    // [px]
  int height = 960;    // [px]
  double fx = 1108.5;  // [px]
  double fy = 1108.5;  // [px]
  double cx = 639.5;   // [px]
  double cy = 479.5;   // [px]

  // Square pixels, principal point at the image centre, the given horizontal field of view.
  static CameraIntrinsics FromHorizontalFov(int width, int height, double hfov_deg);
  // Pixel of a point in the optical frame; z must be positive.
  Eigen::Vector2d Project(const Eigen::Vector3d& p_optical) const {
    return {fx * p_optical.x() / p_optical.z() + cx, fy * p_optical.y() / p_optical.z() + cy};
  }
};

// The stereo pair: left camera placed on the tanker, right camera `baseline` to its right along
// the left optical x axis (rectified: same intrinsics and orientation).
struct StereoRig {
  CameraIntrinsics intrinsics = CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0);
  double baseline = 0.5;  // [m]
  Eigen::Isometry3d T_tanker_left_optical = Eigen::Isometry3d::Identity();

  Eigen::Isometry3d T_tanker_right_optical() const {
    return T_tanker_left_optical * Eigen::Translation3d(baseline, 0.0, 0.0);
  }
};

// A rig whose centre sits at `centre_in_tanker` [m], looking along the tanker heading turned by
// `yaw_deg` (180: aft) and pitched down by `pitch_down_deg`. Default (docs/ARCHITECTURE.md,
// Frames): 20 m aft, 3 m below the tanker origin, looking aft, 25 deg down; and 1 m left of the
// boom's plane: on the plane, every line of sight 6 to 22 deg below the horizon crosses the boom,
// which hides a receiver beyond about 100 m completely (0 stereo points at 174 m; 79 with the
// offset).
StereoRig MakeStereoRig(const CameraIntrinsics& intrinsics, double baseline,
                        const Eigen::Vector3d& centre_in_tanker = {-20.0, 1.0, -3.0},
                        double yaw_deg = 180.0, double pitch_down_deg = 25.0);

}  // namespace aar_sim
