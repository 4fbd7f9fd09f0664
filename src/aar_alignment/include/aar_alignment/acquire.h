#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "aar_alignment/aligner.h"

namespace aar_alignment {

// Acquisition from the images alone (issue 27; not in the thesis): where stereo gives the tracker
// nothing to start from (far out the receiver yields a few dozen points, and behind the boom
// none), its silhouette at the expected attitude is searched over the whole left image of every
// rig (the input's left and each further rig's left extra view; with both_views, every image) at
// ranges from min_range to max_range along that camera's axis (SearchShift at each, the boom
// masked; with stereo's cue, only around it), the placements whose outline fits best
// (OutlineAligner::Score) are aligned in every image (OutlineAligner::Align, from a prior long
// along the line of sight of the camera it was found in: the outline's size fixes the range), and
// the best fit is the result.
struct AcquisitionOptions {
  double min_range = 50.0;   // [m] from the left camera along its axis
  double max_range = 200.0;  // [m]
  double range_step = 1.15;  // ratio of neighbouring ranges searched
  int template_size = 32;    // [px] the silhouette's size in the image-wide search
  int candidates = 3;        // placements aligned: those that fit best (one per range)
  // Share of the outline's lines that must be seen (inside the image, not behind the boom), at a
  // placement and at its alignment: a silhouette mostly behind the boom fits on its few visible
  // lines in many wrong places (far out, farther and smaller receivers whose fuselage the boom
  // hides fit the real one's wingtips).
  double min_visible = 0.6;
  // Search the right images too, and count a placement or an alignment as seen when any view
  // sees min_visible of its own outline (false: each rig's left image, and seen when a rig sees
  // min_visible with its two views' lines together). Far out the cameras, 0.5 m apart with the
  // boom a few metres away, may see it differently: the boom hid 90 % of a receiver from the left
  // camera that the right one saw whole.
  bool both_views = false;
  // The prior of an alignment from a placement: across the line of sight [m], about the expected
  // attitude [rad]; along the line of sight it is the range grid's step at that range.
  double sigma_across = 1.0;
  double sigma_rotation = 0.05;
  // Stereo's cue (Acquire's `cue`): where at least cue_min_points of its points between
  // min_range and max_range in front of a searched camera lie within the receiver's radius of
  // one of them in its image, that image is searched only around their median pixel (the largest
  // such group's), as far as the receiver's radius reaches at each range and cue_margin_px more.
  // Over terrain and clouds the receiver is seldom the image's best placement, but far out stereo
  // still puts most of its points in that range band on it (the boom is nearer, the ground
  // beyond max_range). Fewer, or scattered: the whole image. 0: no cue.
  int cue_min_points = 0;
  double cue_margin_px = 16.0;  // [px]
  // And only at the ranges whose disparity lies within this of the cue's (its points' median
  // depth, at the first rig's baseline): stereo measures the range too, to sigma_d (about 0.25
  // px) a point. Without it, around the cue's pixel the search fitted an RQ-4 at 132 m 70 m too
  // far on its slender wings, with none of stereo's points on it (suite approach 7003). 0: every
  // range.
  double cue_disparity_margin_px = 0.0;

  // Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

struct AcquisitionResult {
  bool valid = false;  // an alignment; otherwise `error` says why not
  std::string error;
  AlignmentResult alignment;  // the best fitting of the aligned placements
  double range_m = 0.0;       // [m] the range of the placement it was aligned from
  double search_score = 0.0;  // that placement's search score (SearchShiftResult::score)
  int ranges = 0;             // ranges whose search found a placement
  int aligned = 0;            // placements aligned
  double time_ms = 0.0;
};

// The share of an alignment's outline seen (inside the image, not behind the boom). Without
// both_views, that of the rig that sees most of its own, each rig's two views' lines together
// (one rig: both views' lines together, r.lines / r.outline_lines); with both_views, that of the
// view that sees most of its own, over every rig's views.
double SeenShare(const AcquisitionOptions& options, const AlignmentResult& r);

// `in`'s images (extra_views too), cameras and boom; its predicted pose gives only the attitude
// searched at (its position is ignored). Never throws for bad images (valid = false and why).
// `cue`: stereo's points [m, tanker frame] (options.cue_min_points).
AcquisitionResult Acquire(const OutlineAligner& aligner, const AlignmentInput& in,
                          const AcquisitionOptions& options = {},
                          const std::vector<Eigen::Vector3d>& cue = {});

}  // namespace aar_alignment
