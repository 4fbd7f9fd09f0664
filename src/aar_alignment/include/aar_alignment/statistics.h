#pragma once

#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace aar_alignment {

// Per grey level, the probability that a pixel of that grey is the receiver rather than what
// lies around it, from grey-level histograms of `bins` bins.
class GreyPosterior {
 public:
  GreyPosterior() = default;

  // From the background (pixels known to lie off the receiver) and a neighbourhood of the
  // receiver (receiver and background in unknown shares, as when the prediction is off): the
  // receiver's histogram is the neighbourhood's minus the largest multiple of the background's
  // that leaves every bin non-negative.
  static GreyPosterior FromNeighbourhood(const std::vector<float>& background,
                                         const std::vector<float>& neighbourhood, int bins);
  // From pixels labelled receiver and background (by the predicted outline).
  static GreyPosterior FromLabels(const std::vector<float>& receiver,
                                  const std::vector<float>& background, int bins);

  bool empty() const { return p_.empty(); }
  float operator()(float grey) const {
    return p_[std::min(static_cast<int>(p_.size()) - 1,
                       static_cast<int>(grey * static_cast<float>(p_.size()) / 256.0f))];
  }

 private:
  std::vector<float> p_;
};

// Grey values of the background around the receiver, clean of it whatever the prediction's
// error: on a grid over the ring between `box` [px] grown by `gap` and grown further by half its
// size (at least 32 px), inside the image and off `boom` (CV_8U, 1 on the boom; may be empty);
// about `count` values.
std::vector<float> RingSamples(const cv::Mat& image, const cv::Mat& boom,
                               const Eigen::AlignedBox2d& box, double gap, int count);

}  // namespace aar_alignment
