#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_stereo/sparse_matcher.h"

namespace aar_stereo {

// kSparse (issue 28, not in the thesis): block matching's cost at a grid of samples in the region
// of interest (sparse_matcher.h); a frame without one (acquisition) is block-matched whole.
enum class Matcher { kBlockMatching, kSemiGlobal, kSparse };
enum class Decimation { kNone, kEveryNth, kVoxelGrid };

// Matcher and cloud settings. Defaults: the thesis (block 9, 48 disparities, every 8th point,
// 750 m); the remaining block-matching values are stereo_image_proc's defaults.
struct StereoOptions {
  Matcher matcher = Matcher::kBlockMatching;
  int block_size = 9;             // [px] odd, 5..255 (BM), 1..11 typical (SGBM)
  int num_disparities = 48;       // [px] multiple of 16
  int min_disparity = 0;          // [px]
  int prefilter_size = 9;         // [px] odd, 5..255 (BM)
  int prefilter_cap = 31;         // 1..63
  int texture_threshold = 10;     // BM: minimum texture in the block
  int uniqueness_ratio = 15;      // [%] best match must beat the second by this margin
  int speckle_window_size = 100;  // [px] speckle filter region size; 0 disables
  int speckle_range = 4;          // [px] disparity variation inside a speckle region
  int disp12_max_diff = -1;       // [px] left-right check; negative disables
  int sgbm_p1 = 0;                // SGBM smoothness; 0: 8 * block_size^2
  int sgbm_p2 = 0;                // SGBM smoothness; 0: 32 * block_size^2
  bool sgbm_full_dp = false;      // SGBM: full 8-direction dynamic programming
  // [px] 0 off, 3 or 5 (not in the thesis; issue 16): a median filter over the valid disparities
  // before the cloud, against depth scatter (it biases point-to-point ICP towards the cameras:
  // docs/realism/README.md). Pixels without a match stay without one.
  int median_filter = 0;
  // kSparse: samples per frame (the grid stride is the smallest that keeps to it) and the
  // left-right check [px] that stands in for the speckle filter (negative: off).
  int sparse_budget = 4000;
  int sparse_lr_max_diff = 1;

  double max_range = 750.0;  // [m] points farther along the optical axis are dropped
  Decimation decimation = Decimation::kEveryNth;
  // kEveryNth: keep valid points 0, n, 2n, ... in row-major order (kSparse: on block-matched
  // frames only; a sample grid is its own decimation)
  int keep_every = 8;
  double voxel_size = 0.05;  // [m] kVoxelGrid: one point (the centroid) per occupied voxel
  bool organized = false;    // kNone only: a height x width cloud with NaN where invalid
  bool intensity = false;    // carry the left image's grey level per point

  // Throws std::invalid_argument naming the first setting OpenCV would reject.
  void Validate() const;
};

// The rectified pair's projection matrices as in sensor_msgs/CameraInfo P (3x4, row-major):
// the right camera's P[0][3] = -fx * baseline.
struct StereoGeometry {
  int width = 0, height = 0;   // [px]
  double fx = 0, fy = 0;       // [px] left
  double cx_left = 0, cy = 0;  // [px]
  double cx_right = 0;         // [px]
  double Tx = 0;               // right P[0][3] [px * m]

  double baseline() const { return -Tx / fx; }  // [m]
  // A rectified pair with one principal point [px] and a baseline [m].
  static StereoGeometry Rectified(int width, int height, double fx, double fy, double cx, double cy,
                                  double baseline);
  // 4x4 reprojection matrix: [x y z w]^T = Q [u v d 1]^T (image_geometry's StereoCameraModel).
  cv::Matx44d Q() const;
  // Throws std::invalid_argument naming what is wrong (zero focal length, no baseline, ...).
  void Validate() const;
};

struct CloudPoints {
  std::vector<Eigen::Vector3f> xyz;  // [m] in the left optical frame; NaN where organized+invalid
  std::vector<float> intensity;      // [0, 255] when requested
  std::vector<int> pixel;            // row-major left-image pixel each point came from (voxel
                                     // grid: its first point's); -1 where organized+invalid
  int width = 0, height = 1;         // organized: image size; else (size, 1)
};

struct StereoTimings {
  double matching_ms = 0, reprojection_ms = 0, decimation_ms = 0, total_ms = 0;
};

struct StereoResult {
  cv::Mat disparity;      // CV_32F [px]; invalid pixels hold min_disparity - 1
  cv::Rect valid_window;  // where the matcher can produce disparities (roi included)
  CloudPoints cloud;
  int valid_pixels = 0;   // disparity valid and within max_range
  bool sparse = false;    // matched at samples (kSparse with a region of interest)
  SparseMatches samples;  // when sparse: the grid and its refusals (pixel lists cleared)
  StereoTimings timings;
};

// The smallest rectangle holding the projections of `points` (left optical frame [m]) grown by
// `margin` [px] and clipped to the image: the region of interest for Process. The whole image if
// a point is not in front of the camera; empty if all project outside (Process then matches
// nothing).
cv::Rect ProjectedRoi(const std::vector<Eigen::Vector3d>& points, const StereoGeometry& geometry,
                      int margin);

// The largest disparity [px, matcher units: principal points' offset included] of anything at
// `points` (left optical frame [m]): the nearest one's, plus a pixel; INT_MAX if one is not in
// front of the cameras. With ProjectedRoi, a DisparityZone for the sparse matcher.
int MaxDisparity(const std::vector<Eigen::Vector3d>& points, const StereoGeometry& geometry);

// The corners of `box` (a body's bounding box in its own frame [m]) grown by `grow` [m] on every
// side and placed by T_optical_body: with ProjectedRoi, the region where a predicted receiver can
// appear.
std::vector<Eigen::Vector3d> BoxCorners(const Eigen::AlignedBox3d& box,
                                        const Eigen::Isometry3d& T_optical_body, double grow);

// Disparity and point cloud from a rectified mono8 pair. `roi`, when given, restricts matching to
// a region of the left image (the rest is invalid; an empty region matches nothing).
class StereoProcessor {
 public:
  explicit StereoProcessor(const StereoOptions& options);  // throws std::invalid_argument
  const StereoOptions& options() const { return options_; }

  // Throws std::invalid_argument for images that are empty, not CV_8UC1, of different sizes or
  // of a size other than the geometry's. `zones` bound the sparse matcher's search (ignored by
  // the dense matchers).
  StereoResult Process(const cv::Mat& left, const cv::Mat& right, const StereoGeometry& geometry,
                       const std::optional<cv::Rect>& roi = std::nullopt,
                       const std::vector<DisparityZone>& zones = {}) const;

 private:
  // Dense matching of `roi` into result->disparity (float, shifted for the principal points).
  void MatchDense(const cv::Mat& left, const cv::Mat& right, const cv::Rect& roi, float shift,
                  StereoResult* result) const;
  // Sparse matching of `roi`; returns the matched pixels, the disparity image holding them.
  std::vector<int> MatchAtSamples(const cv::Mat& left, const cv::Mat& right, const cv::Rect& roi,
                                  const std::vector<DisparityZone>& zones, float shift,
                                  StereoResult* result) const;
  void Decimate(const cv::Mat& left, const std::vector<Eigen::Vector3f>& points,
                const std::vector<int>& pixels, bool sparse, CloudPoints* cloud) const;
  void VoxelGrid(const cv::Mat& left, const std::vector<Eigen::Vector3f>& points,
                 const std::vector<int>& pixels, CloudPoints* cloud) const;

  StereoOptions options_;
};

}  // namespace aar_stereo
