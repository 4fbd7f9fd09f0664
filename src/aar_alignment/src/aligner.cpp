#include "aar_alignment/aligner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <aar_geometry/pose.h>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "aar_alignment/boom_parts.h"
#include "aar_alignment/search.h"
#include "aar_alignment/statistics.h"
#include "line_model.h"

namespace aar_alignment {
namespace {

using line_model::Distribution;
using line_model::Line;
using line_model::LineShape;
using line_model::Posterior;
using line_model::Sample;
using line_model::Smoothed;
using line_model::View;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The line's row of the Gauss-Newton system: d(offset of the projected outline along the normal)
// / d(pose error [dp, dtheta]) at the pose (R, p).
Eigen::Matrix<double, 1, 6> Jacobian(const View& v, const Eigen::Matrix3d& R,
                                     const Eigen::Vector3d& p, const Line& l) {
  const Eigen::Vector3d offset = R * l.body;
  const Eigen::Vector3d y = v.T_optical_tanker * (offset + p);
  const PinholeCamera& c = *v.camera;
  Eigen::Matrix<double, 2, 3> du;
  du << c.fx / y.z(), 0.0, -c.fx * y.x() / (y.z() * y.z()), 0.0, c.fy / y.z(),
      -c.fy * y.y() / (y.z() * y.z());
  const Eigen::Matrix<double, 2, 3> A = du * v.T_optical_tanker.linear();
  Eigen::Matrix<double, 2, 6> J;
  J << A, -A * Skew(offset);
  return l.normal.transpose() * J;
}

struct Pass {
  std::vector<Line> lines;
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  int usable = 0;
  std::vector<int> view_usable;  // per view
  double fit = 0.0;              // sum over usable lines of Line::fit
  int inliers = 0;
};

// Lines through the outline points at the pose, their statistics and the Gauss-Newton system.
// `expected` holds each contour point's smoothed profile (Line::expected). Every sum runs over
// the views in order, so views appended after the first rig's leave its figures as they were.
using Expectations = std::vector<std::vector<std::vector<float>>>;  // [view][point][pixel]
Pass Evaluate(const AlignmentOptions& o, const std::vector<View>& views,
              const std::vector<std::vector<ContourPoint>>& contours, const Expectations& expected,
              const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double scale) {
  Pass pass;
  pass.view_usable.assign(views.size(), 0);
  const LineShape shape(o, scale);
  for (size_t v = 0; v < views.size(); ++v) {
    const Eigen::Isometry3d T = views[v].T_optical_tanker;
    const PinholeCamera& c = *views[v].camera;
    for (size_t k = 0; k < contours[v].size(); ++k) {
      const ContourPoint& cp = contours[v][k];
      Line l;
      l.view = static_cast<int>(v);
      l.body = cp.body;
      l.normal = cp.normal;
      l.expected = &expected[v][k];
      const Eigen::Vector3d y = T * (R * cp.body + p);
      if (!(y.z() > 0.1)) continue;
      l.center = c.Project(y);
      Sample(views[v], shape, l);
      pass.lines.push_back(std::move(l));
    }
  }
  for (size_t v = 0; v < views.size(); ++v) {
    const GreyPosterior posterior = o.line_model == LineModel::kRegion
                                        ? Posterior(views[v], pass.lines, static_cast<int>(v),
                                                    contours[v], shape, o.histogram_bins)
                                        : GreyPosterior();
    for (Line& l : pass.lines)
      if (l.view == static_cast<int>(v)) Distribution(shape, o.line_model, posterior, l);
  }
  for (const Line& l : pass.lines) {
    if (!l.usable) continue;
    ++pass.usable;
    ++pass.view_usable[l.view];
    const Eigen::Matrix<double, 1, 6> j = Jacobian(views[l.view], R, p, l);
    pass.H += j.transpose() * j / l.variance;
    pass.g += j.transpose() * l.mean / l.variance;
    pass.inliers += l.fit > 0.5;
    pass.fit += l.fit;
  }
  return pass;
}

// The prediction's information: the inverse of its covariance, or the options' prior.
Matrix6d PriorInformation(const AlignmentOptions& o, const Matrix6d& covariance) {
  if (covariance.allFinite() && covariance.trace() > 0.0) {
    const Eigen::LDLT<Matrix6d> ldlt(covariance);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) return ldlt.solve(Matrix6d::Identity());
  }
  Vector6d d;
  d << Eigen::Vector3d::Constant(1.0 / (o.prior_sigma_position * o.prior_sigma_position)),
      Eigen::Vector3d::Constant(1.0 / (o.prior_sigma_rotation * o.prior_sigma_rotation));
  return d.asDiagonal();
}

// What is wrong with one view's image or camera, `name` the view's ("left"); empty when nothing.
std::string CheckView(const std::string& name, const cv::Mat& m, const PinholeCamera& c) {
  if (m.empty()) return "the " + name + " image is empty";
  if (m.type() != CV_8UC1) return "the " + name + " image is not mono8";
  if (!(c.fx > 0.0 && c.fy > 0.0) || c.width < 2 || c.height < 2)
    return "the " + name + " camera has no size or focal length";
  if (m.cols != c.width || m.rows != c.height)
    return "the " + name + " image's size differs from its camera's";
  return "";
}

}  // namespace

std::string CheckAlignmentInput(const AlignmentInput& in) {
  std::string error = CheckView("left", in.left, in.left_camera);
  if (error.empty()) error = CheckView("right", in.right, in.right_camera);
  if (!error.empty()) return error;
  if (in.extra_views.size() % 2 != 0)
    return "extra_views holds " + std::to_string(in.extra_views.size()) +
           " views, not a left and a right per further rig";
  for (size_t i = 0; i < in.extra_views.size(); ++i) {
    const aar_alignment::View& v = in.extra_views[i];  // the input's, not line_model::View
    error = CheckView("extra_views[" + std::to_string(i) + "]", v.image, v.camera);
    if (!error.empty()) return error;
  }
  if (!in.T_tanker_receiver_predicted.matrix().allFinite())
    return "the predicted pose is not finite";
  return "";
}

LineModel ParseLineModel(const std::string& name) {
  if (name == "region") return LineModel::kRegion;
  if (name == "contrast") return LineModel::kContrast;
  throw std::invalid_argument("line_model must be region or contrast, not '" + name + "'");
}

std::string ToString(LineModel model) {
  return model == LineModel::kRegion ? "region" : "contrast";
}

void AlignmentOptions::Validate() const {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("alignment option " + what);
  };
  if (scales.empty()) fail("scales: needs at least one stage");
  for (const double s : scales)
    if (!(s >= 1.0 && s <= 16.0) || s != std::floor(s))
      fail("scales: each must be a whole number of pixels in [1, 16]");
  if (iterations_per_scale < 1) fail("iterations_per_scale must be at least 1");
  if (line_samples < 4 || line_samples % 2 != 0 || line_samples > 64)
    fail("line_samples must be even, in [4, 64]");
  if (step_window < 2 || step_window % 2 != 0 || step_window > line_samples)
    fail("step_window must be even, in [2, line_samples]");
  if (contour_points < 8) fail("contour_points must be at least 8");
  if (mask_size < 32) fail("mask_size must be at least 32");
  if (!(mask_max_scale > 0.0)) fail("mask_max_scale must be > 0");
  if (histogram_bins < 2 || histogram_bins > 256) fail("histogram_bins must lie in [2, 256]");
  if (!(step_amplitude > 0.0 && step_amplitude < 0.5)) fail("step_amplitude must lie in (0, 0.5)");
  if (!(step_slope > 0.0)) fail("step_slope must be positive");
  if (!(boom_margin_px >= 0.0)) fail("boom_margin_px must not be negative");
  if (!(covariance_scale > 0.0)) fail("covariance_scale must be positive");
  if (!(prior_sigma_position > 0.0) || !(prior_sigma_rotation > 0.0))
    fail("prior_sigma_position and prior_sigma_rotation must be positive");
  if (min_lines < 6) fail("min_lines must be at least 6");
}

OutlineAligner::OutlineAligner(const aar_geometry::TriangleMesh& receiver,
                               const AlignmentOptions& options)
    : options_(options), model_(receiver) {
  options_.Validate();
}

// The state of one alignment: every view (the first rig's left and right, then the extra views),
// the pose and the outline at it.
class OutlineAligner::Run {
 public:
  Run(const OutlineAligner& aligner, const AlignmentInput& in)
      : o_(aligner.options_), model_(aligner.model_), in_(in) {
    AddView(in.left, in.left_camera);
    AddView(in.right, in.right_camera);
    for (const aar_alignment::View& v : in.extra_views) AddView(v.image, v.camera);
    contours_.resize(views_.size());
    expected_.resize(views_.size());
    R_ = R0_ = in.T_tanker_receiver_predicted.linear();
    p_ = p0_ = in.T_tanker_receiver_predicted.translation();
    prior_ = PriorInformation(o_, in.prediction_covariance);
    // The profile reaches past every stage's line and shift.
    for (const double scale : o_.scales) {
      const LineShape shape(o_, scale);
      profile_half_ = std::max(
          profile_half_,
          shape.pixels / 2 + 2 + static_cast<int>(std::ceil(0.5 * (shape.hypotheses - 1) * scale)));
    }
  }

  Eigen::Isometry3d Pose() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(R_).normalized().toRotationMatrix();
    T.translation() = p_;
    return T;
  }

  // The outline at the current pose in every view; false when there is none.
  bool Outline() {
    size_t points = 0;
    for (size_t i = 0; i < views_.size(); ++i) {
      contours_[i] = model_.Contour(*views_[i].camera, Pose(), o_.contour_points, profile_half_,
                                    o_.mask_size, o_.mask_max_scale);
      points += contours_[i].size();
      expected_[i].clear();
      for (const ContourPoint& cp : contours_[i])
        expected_[i].push_back(
            Smoothed(cp.profile, static_cast<int>(std::lround(o_.step_slope)), o_.step_amplitude));
    }
    return points > 0;
  }

  // [px] the prediction's standard deviation in the left image: across the line of sight, and
  // of the receiver's extremities (its mesh's radius) turned by the rotation's.
  double UncertaintyPx() const {
    const Eigen::Vector3d y = views_[0].T_optical_tanker * p_;
    const Eigen::Matrix3d R_ot = views_[0].T_optical_tanker.linear();
    const Matrix6d covariance = prior_.inverse();
    const Eigen::Matrix3d position = R_ot * covariance.topLeftCorner<3, 3>() * R_ot.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> across(position.topLeftCorner<2, 2>());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> turn(covariance.bottomRightCorner<3, 3>());
    const double metres = std::sqrt(std::max(0.0, across.eigenvalues().maxCoeff())) +
                          std::sqrt(std::max(0.0, turn.eigenvalues().maxCoeff())) * model_.radius();
    return metres * in_.left_camera.fx / std::max(1.0, y.z());
  }

  // [px] how far the lines of a stage look for the outline each way.
  double Reach(double scale) const {
    const LineShape shape(o_, scale);
    return 0.5 * (shape.hypotheses - 1) * shape.spacing;
  }

  // SearchShift in the left view over three standard deviations of the prediction (at most
  // search_radius_px); skipped when the first stage's lines reach that far. The shift applied.
  Eigen::Vector2d Search() {
    ShiftSearchOptions search;
    search.radius_px = std::min(o_.search_radius_px, 3.0 * UncertaintyPx());
    if (search.radius_px <= Reach(o_.scales.front())) return Eigen::Vector2d::Zero();
    search.template_size = o_.search_template_size;
    const ShiftSearchResult shift =
        SearchShift(model_, in_.left, views_[0].boom, in_.left_camera, Pose(), search);
    if (!shift.valid) return Eigen::Vector2d::Zero();
    // Kept only when the outline fits better there than at the prediction (the search sees one
    // view at a coarse scale, and clutter such as the boom's edges can win it).
    const double before = Fit();
    const Eigen::Vector3d unshifted = p_;
    p_ = shift.T_tanker_receiver.translation();
    if (Fit() > before) return shift.shift_px;
    p_ = unshifted;
    return Eigen::Vector2d::Zero();
  }

  // The mean fit of the outline at the current pose (finest scale).
  double Fit() {
    if (!Outline()) return 0.0;
    const Pass pass = Evaluate(o_.scales.back());
    return pass.usable > 0 ? pass.fit / pass.usable : 0.0;
  }

  Pass Evaluate(double scale) const {
    return aar_alignment::Evaluate(o_, views_, contours_, expected_, R_, p_, scale);
  }

  // One Gauss-Newton step of the MAP estimate (the lines and the prediction); the deviation from
  // the prediction is in the error coordinates (position, left rotation vector).
  bool Step(const Pass& pass) {
    const Eigen::AngleAxisd turn(R_ * R0_.transpose());
    Vector6d deviation;
    deviation << p_ - p0_, turn.angle() * turn.axis();
    const Vector6d step = (pass.H + prior_).ldlt().solve(pass.g - prior_ * deviation);
    if (!step.allFinite()) return false;
    p_ += step.head<3>();
    R_ = aar_geometry::RotationExp(step.tail<3>()) * R_;
    return true;
  }

  // The result's figures from a pass at the current pose.
  void Finish(const Pass& last, AlignmentResult& out) const {
    out.lines = last.usable;
    out.view_lines = last.view_usable;
    out.view_outline_lines.clear();
    for (const std::vector<ContourPoint>& contour : contours_)
      out.view_outline_lines.push_back(static_cast<int>(contour.size()));
    out.outline_lines =
        std::accumulate(out.view_outline_lines.begin(), out.view_outline_lines.end(), 0);
    out.information = last.H / (o_.covariance_scale * SharedRigs(last));
    out.covariance = (out.information + prior_).inverse();
    out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
    out.T_tanker_receiver = Pose();
    out.quality = last.usable > 0 ? last.fit / last.usable : 0.0;
    out.inlier_share = last.usable > 0 ? static_cast<double>(last.inliers) / last.usable : 0.0;
  }

 private:
  // The information's divisor for rigs that share their errors (rigs_share_errors): the number
  // of rigs (a left and a right view each, in order) with usable lines; 1 otherwise.
  double SharedRigs(const Pass& pass) const {
    if (!o_.rigs_share_errors) return 1.0;
    int rigs = 0;
    for (size_t v = 0; v + 1 < pass.view_usable.size(); v += 2)
      rigs += pass.view_usable[v] + pass.view_usable[v + 1] > 0 ? 1 : 0;
    return std::max(1, rigs);
  }

  // One view as the stages see it: its boom mask and the camera's inverse pose.
  void AddView(const cv::Mat& image, const PinholeCamera& camera) {
    line_model::View v;
    v.image = &image;
    v.camera = &camera;
    v.T_optical_tanker = camera.T_tanker_optical.inverse();
    v.boom = BoomMask(camera, in_.boom_parts_in_tanker, o_.boom_margin_px);
    views_.push_back(std::move(v));
  }

  const AlignmentOptions& o_;
  const OutlineModel& model_;
  const AlignmentInput& in_;
  std::vector<line_model::View> views_;  // left, right, then the extra views
  Eigen::Matrix3d R_, R0_;
  Eigen::Vector3d p_, p0_;
  Matrix6d prior_;
  int profile_half_ = 0;
  std::vector<std::vector<ContourPoint>> contours_;  // per view
  Expectations expected_;                            // of contours_
};

namespace {

std::string TooFewLines(int usable, int min_lines, const std::string& where) {
  return "only " + std::to_string(usable) + " usable outline lines " + where + " (min_lines " +
         std::to_string(min_lines) + ")";
}

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

constexpr const char* kNoOutline =
    "the receiver at the pose has no outline in any image (behind a camera?)";

}  // namespace

AlignmentResult OutlineAligner::Align(const AlignmentInput& in) const {
  const auto start = std::chrono::steady_clock::now();
  AlignmentResult out;
  out.error = CheckAlignmentInput(in);
  if (!out.error.empty()) return out;
  Run run(*this, in);
  if (options_.search_radius_px > 0.0) out.search_shift_px = run.Search();
  // Without a search, coarse stages whose next one already reaches three standard deviations of
  // the prediction are skipped (a tracked receiver near contact needs only the fine ones).
  size_t first = 0;
  const double sigma_px = run.UncertaintyPx();
  while (out.search_shift_px.isZero() && first + 1 < options_.scales.size() &&
         run.Reach(options_.scales[first + 1]) >= 3.0 * sigma_px)
    ++first;
  for (size_t stage = first; stage < options_.scales.size(); ++stage) {
    const double scale = options_.scales[stage];
    if (!run.Outline()) {
      out.error = kNoOutline;
      return out;
    }
    for (int it = 0; it < options_.iterations_per_scale; ++it, ++out.iterations) {
      const Pass pass = run.Evaluate(scale);
      if (pass.usable < options_.min_lines) {
        out.error = TooFewLines(pass.usable, options_.min_lines,
                                "at scale " + std::to_string(static_cast<int>(scale)) + " px");
        return out;
      }
      if (!run.Step(pass)) {
        out.error = "the Gauss-Newton step is not finite";
        return out;
      }
    }
  }
  // The result's figures from the last stage's outline points, reprojected at the final pose
  // (the fine stage moved it by a pixel or two: the points, normals and profiles still hold).
  const Pass last = run.Evaluate(options_.scales.back());
  run.Finish(last, out);
  out.valid = last.usable >= options_.min_lines && out.covariance.allFinite();
  if (last.usable < options_.min_lines)
    out.error = TooFewLines(last.usable, options_.min_lines, "at the result");
  else if (!out.valid)
    out.error = "the covariance is not finite";
  out.time_ms = MsSince(start);
  return out;
}

AlignmentResult OutlineAligner::Score(const AlignmentInput& in) const {
  const auto start = std::chrono::steady_clock::now();
  AlignmentResult out;
  out.error = CheckAlignmentInput(in);
  if (!out.error.empty()) return out;
  Run run(*this, in);
  if (!run.Outline()) {
    out.error = kNoOutline;
    return out;
  }
  const Pass pass = run.Evaluate(options_.scales.back());
  run.Finish(pass, out);
  out.valid = pass.usable >= options_.min_lines;
  if (!out.valid) out.error = TooFewLines(pass.usable, options_.min_lines, "at the pose");
  out.time_ms = MsSince(start);
  return out;
}

}  // namespace aar_alignment
