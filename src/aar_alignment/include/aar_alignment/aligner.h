#pragma once

#include <string>
#include <vector>

#include <aar_geometry/triangle_mesh.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "aar_alignment/outline.h"

namespace aar_alignment {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// How a line judges where the outline lies along it.
enum class LineModel {
  // Receiver and background grey-level statistics (SRT3D's region model): the ring around the
  // receiver against its neighbourhood. Strong where the background is plain (sky).
  kRegion,
  // Local contrast: the line's own pixels split by the shifted outline profile into two classes
  // of their own mean grey. Needs no statistics, so terrain and clouds with the receiver's grey
  // levels elsewhere in the image do not confuse it.
  kContrast,
};
LineModel ParseLineModel(const std::string& name);  // region|contrast; throws invalid_argument
std::string ToString(LineModel model);

// Region-based alignment of the receiver's outline in both images (after SRT3D, Stoiber et al.
// 2020/2022: sparse correspondence lines across the projected outline, foreground and background
// grey-level statistics, a Gaussian per line of where the outline lies along it, Gauss-Newton on
// the pose; written from the papers, not their code).
struct AlignmentOptions {
  // Coarse to fine, one stage per entry: the spacing [px, whole] of the hypotheses of where the
  // outline lies along each line; lines are read pixel by pixel.
  std::vector<double> scales = {4.0, 2.0, 1.0};
  int iterations_per_scale = 2;
  // First, the coarse search (SearchShift): the predicted silhouette slid over the left image by
  // three standard deviations of the prediction across the line of sight, at most this many
  // pixels each way; skipped when the first stage's lines reach that far. 0: off.
  double search_radius_px = 48.0;
  int search_template_size = 64;  // [px]
  int line_samples = 16;          // per line, half inside the predicted outline, half outside
  // Samples around each hypothesis of the outline's place that judge it (SRT3D's function
  // length): line_samples - step_window + 1 hypotheses, the central window gives the statistics.
  int step_window = 8;
  int contour_points = 200;     // lines per camera, spread evenly along the outline
  int mask_size = 320;          // [px] the outline's mask resolution (OutlineModel)
  double mask_max_scale = 4.0;  // at most this many mask pixels per image pixel
  int histogram_bins = 32;      // grey-level bins of the foreground and background statistics
  LineModel line_model = LineModel::kContrast;
  // The expected image along a line: the projected mesh's profile averaged over slope x scale px
  // either side, as probabilities 1/2 -+ amplitude (after SRT3D's smoothed step).
  double step_amplitude = 0.43;
  double step_slope = 0.5;
  double boom_margin_px = 3.0;  // [px] the boom's projection grown by this
  // Lines of neighbouring outline points are not independent: the Gauss-Newton information is
  // divided by this (covariance = scale x inverse information).
  double covariance_scale = 4.0;
  // With views of more than one rig (AlignmentInput::extra_views): true takes their errors as
  // shared (the model's and the images' errors, seen from every camera alike), so the information
  // is divided by the number of rigs whose views had usable lines as well: further rigs sharpen
  // the pose, but its covariance claims no more than one rig's. false: every view independent.
  bool rigs_share_errors = false;
  // The prediction's uncertainty when the input gives none (standard deviations, each axis): the
  // alignment is a MAP estimate, so directions the outline hardly sees (range and out-of-plane
  // rotations far out) stay near the prediction instead of wandering.
  double prior_sigma_position = 2.0;   // [m]
  double prior_sigma_rotation = 0.05;  // [rad]
  int min_lines = 30;                  // fewer usable lines in all views together: no alignment

  // Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

// One camera's rectified mono8 image and the camera (its size, intrinsics, place on the tanker).
struct View {
  cv::Mat image;
  PinholeCamera camera;
};

struct AlignmentInput {
  cv::Mat left, right;  // rectified, mono8
  PinholeCamera left_camera, right_camera;
  // Further rigs' images (issue 44), in rig order, each rig's left then right (an even count).
  // The alignment's views are left, right, then these: their lines join the same sums after the
  // first rig's, so without them every result is what one rig gives. Empty: one rig.
  std::vector<View> extra_views;
  Eigen::Isometry3d T_tanker_receiver_predicted = Eigen::Isometry3d::Identity();
  // Of the prediction [m^2, rad^2], position then rotation, tanker frame, rotation
  // left-multiplied (the tracker's); zero: the options' prior_sigma_*.
  Matrix6d prediction_covariance = Matrix6d::Zero();
  // The boom's convex parts at this frame, each as its vertices in the tanker frame: their
  // projections are masked out (nothing behind the boom is seen). Empty: no boom.
  std::vector<std::vector<Eigen::Vector3d>> boom_parts_in_tanker;
};

struct AlignmentResult {
  bool valid = false;  // a pose; otherwise `error` says why not
  std::string error;
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  // [m^2, rad^2] position then rotation, tanker frame, rotation left-multiplied
  // (R_true = Exp(dtheta) R): the tracker's convention. With the prediction's (the posterior).
  Matrix6d covariance = Matrix6d::Zero();
  // What the images alone say at the pose: the Gauss-Newton information [1/m^2, 1/rad^2]
  // divided by covariance_scale (near zero in the directions the outline does not see), for a
  // filter that already holds the prediction.
  Matrix6d information = Matrix6d::Zero();
  // How well the outline at the pose fits the images, in [0, 1]: the mean over the lines of how
  // much more probability each line's distribution puts within 1.5 px of the projected outline
  // than a line without an edge would. Near 0 for a pose that does not fit.
  double quality = 0.0;
  // Share of the final lines whose outline lies within 1.5 px of the projected one (fit > 1/2).
  double inlier_share = 0.0;
  int lines = 0;  // usable lines in the final iteration, every view
  // The outline's lines at the final pose, every view, usable or not (a line is unusable when it
  // leaves the image or crosses the boom): lines / outline_lines is the share of the outline seen.
  int outline_lines = 0;
  // The same per view (left, right, then the extra views in order; 2 + extra_views.size() once
  // the outline was found): one view may see the outline the boom hides from another.
  std::vector<int> view_lines, view_outline_lines;
  Eigen::Vector2d search_shift_px = Eigen::Vector2d::Zero();  // what the coarse search moved
  int iterations = 0;
  double time_ms = 0.0;
};

// What is wrong with the input (empty or non-mono8 images, a camera of zero size or of another
// size than its image, an odd number of extra views, a non-finite prediction); empty when
// nothing is. An extra view is named by its index: "the extra_views[3] image is empty".
std::string CheckAlignmentInput(const AlignmentInput& in);

// Aligns the receiver's mesh to both images, and every further rig's (AlignmentInput::
// extra_views). Thread-safe after construction (Align is const).
class OutlineAligner {
 public:
  // Throws std::invalid_argument for a bad mesh or options.
  OutlineAligner(const aar_geometry::TriangleMesh& receiver, const AlignmentOptions& options = {});

  // Never throws for bad images: a frame without a pose comes back with valid = false and why
  // (empty or non-mono8 images, a camera of zero size, the receiver behind a camera, too few
  // lines).
  AlignmentResult Align(const AlignmentInput& input) const;

  // The figures of the prediction itself, without moving it: quality, inlier share, lines and
  // the information (an integrity check: does the outline at this pose fit the images?).
  AlignmentResult Score(const AlignmentInput& input) const;

  const AlignmentOptions& options() const { return options_; }
  const OutlineModel& model() const { return model_; }

 private:
  class Run;
  AlignmentOptions options_;
  OutlineModel model_;
};

}  // namespace aar_alignment
