// Synthetic views for tests of the outline (aar_alignment's and the packages after it): the
// default rig's cameras and a model drawn by its own silhouette, so that the truth is exact. Not
// used by any node; header-only so that a test needs no library of its own.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_alignment/outline.h"

namespace aar_alignment {
namespace test_images {

// A camera of the default rig (20 m aft of the tanker origin, looking aft, 25 deg down; optical z
// along the view), `x_offset` [m] to the right along the rig's baseline (0 left, 0.5 right) and
// the rig moved by `rig_offset` [m] in the tanker frame.
inline PinholeCamera RigCamera(double x_offset,
                               const Eigen::Vector3d& rig_offset = Eigen::Vector3d::Zero()) {
  PinholeCamera c;
  c.width = 1280, c.height = 960, c.fx = c.fy = 1108.5, c.cx = 639.5, c.cy = 479.5;
  const Eigen::Matrix3d R_tanker_view =
      (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(25.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  Eigen::Matrix3d R_view_optical;  // optical z forward, x right, y down
  R_view_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  c.T_tanker_optical.linear() = R_tanker_view * R_view_optical;
  c.T_tanker_optical.translation() = Eigen::Vector3d(-20.0, 1.0, -3.0) + rig_offset +
                                     c.T_tanker_optical.linear() * Eigen::Vector3d(x_offset, 0, 0);
  return c;
}

// `model` at `truth` drawn into `camera`'s image: grey 90 on sky 180 by each pixel's coverage
// (4 x 4 samples of its silhouette), Gaussian noise of `noise` grey levels from `seed`.
inline cv::Mat Draw(const OutlineModel& model, const PinholeCamera& camera,
                    const Eigen::Isometry3d& truth, double noise, unsigned seed) {
  const SilhouetteMask mask = model.Silhouette(camera, truth, 16000, 4.0);
  cv::Mat image(camera.height, camera.width, CV_8U);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      int covered = 0;
      for (int k = 0; k < 16; ++k)
        covered += mask.At(Eigen::Vector2d(x - 0.375 + 0.25 * (k % 4), y - 0.375 + 0.25 * (k / 4)));
      image.at<uint8_t>(y, x) =
          cv::saturate_cast<uint8_t>(180.0 - 90.0 * covered / 16.0 + gauss(rng));
    }
  }
  return image;
}

}  // namespace test_images
}  // namespace aar_alignment
