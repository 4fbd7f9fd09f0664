// The line model of the outline alignment (aligner.cpp): the correspondence lines across the
// predicted outline, their grey values, and the distribution of the outline's place along each
// (SRT3D's smoothed step, region or contrast likelihood); not installed.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_alignment/aligner.h"
#include "aar_alignment/statistics.h"

namespace aar_alignment::line_model {

constexpr float kUnseen = -1.0f;  // a sample outside the image or on the boom
constexpr double kInlierPx = 1.5;

// One camera of the pair as the stages see it.
struct View {
  const cv::Mat* image = nullptr;
  const PinholeCamera* camera = nullptr;
  Eigen::Isometry3d T_optical_tanker;
  cv::Mat boom;  // CV_8U, 1 where the boom's projection (grown) lies; empty: no boom
};

// A correspondence line across the outline: samples from inside (negative x) to outside.
struct Line {
  int view = 0;
  Eigen::Vector3d body;
  Eigen::Vector2d center, normal;
  // The receiver's expected image along the line, smoothed: the probability that the pixel z px
  // outward of the outline is the receiver is expected[z + half] (ContourPoint::profile); held by
  // the run's outline (Expectation), built once per outline.
  const std::vector<float>* expected = nullptr;
  std::vector<float> grey;            // per pixel along the line (kUnseen: not seen)
  std::vector<float> foreground;      // per pixel: probability of the receiver, or kUnseen
  double mean = 0.0, variance = 0.0;  // [px] where the outline lies along the line
  double fit = 0.0;  // [0, 1] how surely the outline lies within kInlierPx of the prediction
  bool usable = false;
};

// The geometry of a line at one stage of scale s: `pixels` samples one pixel apart, centred on
// the predicted outline (x = i - pixels / 2 + 0.5 [px], inside negative); the outline's place is
// tried at hypotheses s px apart, each judged on the `window` px around it.
struct LineShape {
  int pixels = 0;
  int hypotheses = 0;  // at d_j = (j - (hypotheses - 1) / 2) s [px]
  double spacing = 1.0;
  double window = 0.0;  // [px] either side of a hypothesis

  LineShape(const AlignmentOptions& o, double scale)
      : hypotheses(o.line_samples - o.step_window + 1),
        spacing(scale),
        window(0.5 * o.step_window * scale) {
    pixels = 2 * static_cast<int>(std::ceil(0.5 * (hypotheses - 1) * scale + window));
  }
  double X(int i) const { return i - 0.5 * pixels + 0.5; }
  double D(int j) const { return (j - 0.5 * (hypotheses - 1)) * spacing; }
};

// Reads a line's grey values, one per pixel along it; kUnseen outside the image or on the boom.
void Sample(const View& v, const LineShape& shape, Line& line);

// The smoothed profile (Line::expected): the profile averaged over `radius` px either side, as
// probabilities 1/2 -+ amplitude (SRT3D's smoothed step); beyond the profile, background.
std::vector<float> Smoothed(const std::vector<uint8_t>& profile, int radius, double amplitude);

// The grey statistics of one view: the ring around the receiver against the lines' pixels
// (GreyPosterior::FromNeighbourhood); where the receiver fills the image and leaves no ring,
// the lines' pixels that the predicted outline gives the receiver against the others.
GreyPosterior Posterior(const View& v, const std::vector<Line>& lines, int view,
                        const std::vector<ContourPoint>& contour, const LineShape& shape, int bins);

// The distribution of the outline's place along the line (mean, variance, fit). As
// SRT3D, a line with any pixel unseen (outside the image, on the boom) is not used: an unseen
// pixel favours the hypotheses whose window it lies in.
void Distribution(const LineShape& shape, LineModel model, const GreyPosterior& posterior, Line& l);

}  // namespace aar_alignment::line_model
