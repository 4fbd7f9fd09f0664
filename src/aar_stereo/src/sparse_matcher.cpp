#include "aar_stereo/sparse_matcher.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

namespace aar_stereo {
namespace {

constexpr int kMaxBlocks = 8;                // 16 disparities each: 128 at most
constexpr int kPad = 16 * kMaxBlocks + 256;  // [px] right of the image: whole-vector loads

void Check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// cv::StereoBM's x-Sobel prefilter of `rect`, clamped to [-cap, cap] and offset by cap, written
// into the same place of `dst`. Neighbours outside `rect` come from the image and are reflected
// at its borders (the border columns come out as cap, as StereoBM's).
void Prefilter(const cv::Mat& src, const cv::Rect& rect, int cap, cv::Mat& dst) {
  cv::Mat gradient;
  cv::Sobel(src(rect), gradient, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REFLECT_101);
  cv::Mat clamped = cv::min(cv::max(gradient, -cap), cap);
  clamped.convertTo(dst(cv::Rect(rect.x, rect.y, rect.width, rect.height)), CV_8U, 1.0, cap);
}

// Prefiltered images, padded on the right so that the cost kernel may load whole vectors past
// the last disparity. Zeroed once per size; reused from frame to frame on a thread.
struct Prefiltered {
  cv::Mat left, right;
};
Prefiltered& Buffers(const cv::Size& size) {
  thread_local Prefiltered buffers;
  if (buffers.left.rows != size.height || buffers.left.cols != size.width + kPad) {
    buffers.left = cv::Mat::zeros(size.height, size.width + kPad, CV_8U);
    buffers.right = cv::Mat::zeros(size.height, size.width + kPad, CV_8U);
  }
  return buffers;
}

// costs[k] (k < n) = sum over the block around (xf, y) of |fixed - moving shifted by xm - xf + k|:
// the block matching cost, one disparity per vector lane.
void BlockCosts(const cv::Mat& fixed, int xf, const cv::Mat& moving, int xm, int y, int half, int n,
                uint16_t* costs) {
  const int blocks = (n + 15) / 16;
  cv::v_uint16x8 sums[2 * kMaxBlocks];
  for (int b = 0; b < 2 * blocks; ++b) sums[b] = cv::v_setzero_u16();
  for (int j = -half; j <= half; ++j) {
    const uint8_t* f = fixed.ptr<uint8_t>(y + j) + xf;
    const uint8_t* m = moving.ptr<uint8_t>(y + j) + xm;
    for (int i = -half; i <= half; ++i) {
      const cv::v_uint8x16 fv = cv::v_setall_u8(f[i]);
      for (int b = 0; b < blocks; ++b) {
        cv::v_uint16x8 lo, hi;
        cv::v_expand(cv::v_absdiff(fv, cv::v_load(m + i + 16 * b)), lo, hi);
        sums[2 * b] += lo;
        sums[2 * b + 1] += hi;
      }
    }
  }
  for (int b = 0; b < 2 * blocks; ++b) cv::v_store(costs + 8 * b, sums[b]);
}

int Texture(const cv::Mat& prefiltered, int x, int y, int half, int cap) {
  int sum = 0;
  for (int j = -half; j <= half; ++j) {
    const uint8_t* row = prefiltered.ptr<uint8_t>(y + j) + x;
    for (int i = -half; i <= half; ++i) sum += std::abs(row[i] - cap);
  }
  return sum;
}

int FirstMinimum(const uint16_t* costs, int n) {
  int k = 0;
  for (int i = 1; i < n; ++i)
    if (costs[i] < costs[k]) k = i;
  return k;
}

enum class Verdict { kMatched, kAmbiguous, kAtBound };

// StereoBM's decision over costs[0, n), lane k standing for disparity top - k (the first minimum:
// the larger disparity wins a tie): uniqueness outside the minimum's neighbours, then parabolic
// subpixel interpolation when the minimum has both neighbours. A minimum on the top lane when the
// search was cut short there is refused.
Verdict Decide(const uint16_t* costs, int n, int top, int uniqueness, bool open_top, int16_t* d16) {
  const int k = FirstMinimum(costs, n);
  if (uniqueness > 0) {
    const int threshold = costs[k] + costs[k] * uniqueness / 100;
    for (int i = 0; i < n; ++i)
      if ((i < k - 1 || i > k + 1) && costs[i] <= threshold) return Verdict::kAmbiguous;
  }
  if (k == 0 && open_top) return Verdict::kAtBound;
  if (0 < k && k < n - 1) {
    const int p = costs[k + 1], m = costs[k - 1];
    const int den = p + m - 2 * costs[k] + std::abs(p - m);
    *d16 = static_cast<int16_t>(((top - k) * 256 + (den != 0 ? (p - m) * 256 / den : 0) + 15) >> 4);
  } else {
    *d16 = static_cast<int16_t>((top - k) * 16);
  }
  return Verdict::kMatched;
}

struct Range {
  int lo, hi;  // [px] inclusive
};

// The disparities a sample at (x, y) searches: the full range without zones, else up to the
// largest bound of the zones holding it (lo > hi: none holds it).
Range SearchRange(int x, int y, const std::vector<DisparityZone>& zones, const Range& full) {
  if (zones.empty()) return full;
  int hi = full.lo - 1;
  for (const auto& z : zones)
    if (z.region.contains(cv::Point(x, y))) hi = std::max(hi, z.max_disparity);
  return {full.lo, std::min(hi, full.hi)};
}

// Left-right check: the right pixel's best match back along the left row, within the same search
// range, lies within `max_diff` of the sample's disparity.
bool Consistent(const Prefiltered& p, int x, int y, int d16, const Range& r, int half,
                int max_diff) {
  const int d = (d16 + 8) >> 4;
  const int xr = x - d;
  const int n = std::min(r.hi - r.lo + 1, p.left.cols - kPad - half - (xr + r.lo));
  if (n <= 0) return false;
  uint16_t costs[16 * kMaxBlocks];
  BlockCosts(p.right, xr, p.left, xr + r.lo, y, half, n, costs);
  return std::abs(r.lo + FirstMinimum(costs, n) - d) <= max_diff;
}

int GridCount(int start, int length, int stride) {
  if (length <= 0) return 0;
  const int first = (start + stride - 1) / stride, last = (start + length - 1) / stride;
  return std::max(0, last - first + 1);
}

}  // namespace

void SparseMatchOptions::Validate() const {
  Check(block_size % 2 == 1 && block_size >= 5 && block_size <= 255,
        "sparse matcher: block_size must be odd, 5..255, not " + std::to_string(block_size));
  Check(min_disparity >= 0,
        "sparse matcher: min_disparity must be >= 0, not " + std::to_string(min_disparity));
  Check(num_disparities > 0 && num_disparities % 16 == 0 && num_disparities <= 16 * kMaxBlocks,
        "sparse matcher: num_disparities must be a multiple of 16 up to " +
            std::to_string(16 * kMaxBlocks) + ", not " + std::to_string(num_disparities));
  Check(prefilter_cap >= 1 && prefilter_cap <= 31,
        "sparse matcher: prefilter_cap must be 1..31 (16-bit costs), not " +
            std::to_string(prefilter_cap));
  Check(texture_threshold >= 0 && uniqueness_ratio >= 0,
        "sparse matcher: texture_threshold and uniqueness_ratio must not be negative");
  Check(budget >= 1, "sparse_budget must be at least 1, not " + std::to_string(budget));
}

int SampleStride(const cv::Rect& region, int budget) {
  if (region.area() <= 0) return 1;
  int s = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(region.area()) / budget)));
  while (static_cast<int64_t>(GridCount(region.x, region.width, s)) *
             GridCount(region.y, region.height, s) >
         budget)
    ++s;
  return s;
}

SparseMatches MatchSparse(const cv::Mat& left, const cv::Mat& right, const cv::Rect& region,
                          const std::vector<DisparityZone>& zones, const SparseMatchOptions& o) {
  o.Validate();
  Check(!left.empty() && left.type() == CV_8UC1 && right.type() == CV_8UC1 &&
            left.size() == right.size(),
        "sparse matcher: images must be mono8 and of one size");
  const cv::Rect full(0, 0, left.cols, left.rows);
  const cv::Rect window =
      cv::getValidDisparityROI(full, full, o.min_disparity, o.num_disparities, o.block_size) &
      region;
  SparseMatches out;
  out.stride = SampleStride(region, o.budget);
  if (window.area() <= 0) return out;
  const int half = o.block_size / 2, s = out.stride;
  const Range all{o.min_disparity, o.min_disparity + o.num_disparities - 1};
  // What the samples' blocks and searches (both directions) read.
  const int reach = all.hi + half + 1;
  const cv::Rect need = cv::Rect(window.x - reach, window.y - half, window.width + 2 * reach,
                                 window.height + 2 * half) &
                        full;
  Prefiltered& p = Buffers(left.size());
  Prefilter(left, need, o.prefilter_cap, p.left);
  Prefilter(right, need, o.prefilter_cap, p.right);

  uint16_t costs[16 * kMaxBlocks];
  const int y0 = (window.y + s - 1) / s * s, x0 = (window.x + s - 1) / s * s;
  for (int y = y0; y < window.y + window.height; y += s) {
    for (int x = x0; x < window.x + window.width; x += s) {
      const Range r = SearchRange(x, y, zones, all);
      if (r.lo > r.hi) continue;
      ++out.samples;
      if (Texture(p.left, x, y, half, o.prefilter_cap) < o.texture_threshold) {
        ++out.untextured;
        continue;
      }
      const int n = r.hi - r.lo + 1;
      BlockCosts(p.left, x, p.right, x - r.hi, y, half, n, costs);
      int16_t d16 = 0;
      const Verdict v = Decide(costs, n, r.hi, o.uniqueness_ratio, r.hi < all.hi, &d16);
      if (v == Verdict::kAmbiguous) {
        ++out.ambiguous;
      } else if (v == Verdict::kAtBound) {
        ++out.at_bound;
      } else if (o.lr_max_diff >= 0 && !Consistent(p, x, y, d16, r, half, o.lr_max_diff)) {
        ++out.inconsistent;
      } else {
        out.pixel.push_back(y * left.cols + x);
        out.disparity16.push_back(d16);
      }
    }
  }
  return out;
}

}  // namespace aar_stereo
