#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace aar_stereo {

// A region of the left image where nothing can be nearer than a disparity: the predicted
// receiver's box (its nearest point, grown by the prediction's uncertainty) or the boom's
// projection (its known geometry). The search keeps its lower end (min_disparity): the far
// background (terrain, sea, cloud) then still finds its own small disparity instead of a chance
// minimum among the receiver's.
struct DisparityZone {
  cv::Rect region;        // left image [px]
  int max_disparity = 0;  // [px] inclusive
};

// OpenCV block matching's cost and checks, evaluated at sample pixels only (issue 28). The
// defaults are the thesis's block matching (9x9 SAD over x-Sobel prefiltered images capped at 31,
// 48 disparities, texture 10, uniqueness 15 %).
struct SparseMatchOptions {
  int block_size = 9;          // [px] odd, 5..255
  int min_disparity = 0;       // [px]
  int num_disparities = 48;    // [px] multiple of 16, at most 128
  int prefilter_cap = 31;      // 1..31 (OpenCV's 16-bit costs)
  int texture_threshold = 10;  // sum over the block of |prefiltered - cap|
  int uniqueness_ratio = 15;   // [%]
  // [px] left-right check: the right pixel's best match back in the left image must lie within
  // this of the sample; negative disables. Stands in for the speckle filter (which needs the
  // dense map): a deviation from the thesis.
  int lr_max_diff = 1;
  int budget = 4000;  // samples per frame: the grid stride is the smallest that keeps to it

  void Validate() const;  // throws std::invalid_argument naming the setting
};

struct SparseMatches {
  std::vector<int> pixel;            // row-major left-image pixel of each valid sample
  std::vector<int16_t> disparity16;  // [1/16 px] as cv::StereoBM's output (before any shift)
  int stride = 0;                    // [px] of the sample grid
  int samples = 0;                   // grid pixels in the region and the valid window
  int untextured = 0;                // refused: texture below the threshold
  int ambiguous = 0;                 // refused: a second minimum within the uniqueness ratio
  int at_bound = 0;                  // refused: the best match on the predicted bound (nearer)
  int inconsistent = 0;              // refused: left-right check
};

// The smallest grid stride s >= 1 with at most `budget` grid pixels in `region`. Grid pixels have
// x and y multiples of s (image coordinates: the pattern does not depend on the region's corner).
int SampleStride(const cv::Rect& region, int budget);

// Matches the grid pixels of `region` (left image) that lie where block matching can give a
// disparity (cv::getValidDisparityROI). Without zones each sample searches the full range and the
// result equals cv::StereoBM's (without speckle filter and disp12 check) at that pixel. With
// zones, a sample searches up to the largest max_disparity of the zones holding it (none: not
// sampled), and a best match on that bound, when it cuts the full range, is refused: what is
// there is nearer than predicted. Images: mono8, the same size. Throws std::invalid_argument.
SparseMatches MatchSparse(const cv::Mat& left, const cv::Mat& right, const cv::Rect& region,
                          const std::vector<DisparityZone>& zones, const SparseMatchOptions& o);

}  // namespace aar_stereo
