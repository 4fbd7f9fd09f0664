#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_alignment/outline.h"

namespace aar_alignment {

struct ShiftSearchOptions {
  double radius_px = 48.0;  // [px] the shifts tried, each way, in the image
  int template_size = 64;   // [px] the silhouette is searched at about this size (never larger
                            // than the image's own)
  // A window of uniform grey scores 0 (its noise floor counts as unexplained): for searching the
  // whole image, where most windows are plain sky. Off, such a window scores near 1, and the
  // local search of a tracked receiver, whose shift is kept only where the outline then fits
  // better, stays where the lines alone bring it: measured better from 2 m and 3 deg off at 170 m
  // (alignment_test: mean 0.34 against 0.44 m, worst angle 0.27 against 0.51 deg).
  bool uniform_scores_zero = false;
};

struct ShiftSearchResult {
  bool valid = false;
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // [px] in the image
  double score = 0.0;       // the best shift's share of the window's grey variance explained
  double score_gain = 0.0;  // the best shift's share of grey variance explained over no shift's
  // The prediction moved across the line of sight so that its silhouette lands on the shift.
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
};

// The coarse stage of the alignment: the predicted silhouette slid over the image, each shift
// scored by how much of the grey variance in a window around it the split into receiver and
// background explains (a two-mean fit, as the lines' contrast model; boom pixels left out),
// exhaustively over +-radius on a grid of the template's scale, refined to a fraction of a grid
// step. It finds the prediction's largest error far out, across the line of sight, where the
// outline's lines alone are too short. `boom`: CV_8U, 1 where the boom hides the receiver (may be
// empty). Invalid when the receiver's silhouette spans more than a third of the image either way
// (near contact), or it and a margin around it do not fit in the image.
ShiftSearchResult SearchShift(const OutlineModel& model, const cv::Mat& image, const cv::Mat& boom,
                              const PinholeCamera& camera,
                              const Eigen::Isometry3d& T_tanker_receiver,
                              const ShiftSearchOptions& options = {});

}  // namespace aar_alignment
