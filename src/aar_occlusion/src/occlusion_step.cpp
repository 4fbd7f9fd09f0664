#include "aar_occlusion/occlusion_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace aar_occlusion {
namespace {

// The first of `links` without a pose; empty when all have one.
std::string MissingLink(const std::vector<std::string>& links,
                        const std::map<std::string, Eigen::Isometry3d>& poses) {
  for (const auto& link : links) {
    if (!poses.count(link)) return link;
  }
  return "";
}

// Whether `p` is seen through one of the discs near it: the ray from `eye` to `p` crosses the
// disc's plane within its annulus, and `p` lies within `depth_margin` of that crossing.
bool OnPropeller(const Eigen::Vector3d& eye, const Eigen::Vector3d& p,
                 const std::vector<PropellerDisc>& discs, double margin, double depth_margin) {
  for (const PropellerDisc& d : discs) {
    const Eigen::Vector3d e = eye - d.hub, v = p - eye;
    const double along = v.dot(d.axis);
    if (std::abs(along) < 1e-9) continue;  // the ray runs in the disc's plane
    const double t = -e.dot(d.axis) / along;
    const Eigen::Vector3d q = e + t * v;  // the crossing, relative to the hub
    const double radial = (q - q.dot(d.axis) * d.axis).norm();
    if (radial < d.hub_radius + margin || radial > d.radius + margin) continue;
    if (std::abs(1.0 - t) * v.norm() <= depth_margin) return true;
  }
  return false;
}

// Whether `p` (receiver frame, seen from `eye`) lies in `box`, or on the eye's ray through the box
// within `depth_tolerance` short of where the ray enters it or beyond where it leaves.
bool InGate(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& eye, const Eigen::Vector3d& p,
            double depth_tolerance) {
  if (box.contains(p)) return true;
  const Eigen::Vector3d v = p - eye;
  const double range = v.norm();
  if (!(range > 0.0)) return false;
  const Eigen::Vector3d d = v / range;
  double enter = 0.0, leave = std::numeric_limits<double>::infinity();  // slabs, along the ray
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (eye[k] < box.min()[k] || eye[k] > box.max()[k]) return false;
      continue;
    }
    double t0 = (box.min()[k] - eye[k]) / d[k], t1 = (box.max()[k] - eye[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave && range >= enter - depth_tolerance && range <= leave + depth_tolerance;
}

}  // namespace

OcclusionStep::OcclusionStep(const OcclusionStepOptions& options,
                             const std::optional<aar_geometry::RobotModel>& boom,
                             std::string boom_error, const aar_geometry::TriangleMesh* receiver)
    : options_(options), boom_error_(std::move(boom_error)) {
  if (!(options_.max_point_range > 0.0))
    throw std::invalid_argument("OcclusionStep: max_point_range must be > 0");
  if (boom) {
    try {
      boom_ = std::make_unique<BoomOcclusion>(LoadBoomParts(*boom, options_.parts), options_.boom);
      boom_error_.clear();
    } catch (const std::exception& e) {
      boom_error_ = e.what();
    }
  }
  if (receiver) receiver_radius_ = aar_geometry::HalfDiagonal(receiver->vertices);
  if (options_.gate_receiver) {
    if (receiver == nullptr)
      throw std::invalid_argument("OcclusionStep: the receiver gate needs the receiver mesh");
    if (!(options_.gate_margin >= 0.0) || !(options_.gate_depth_coefficient >= 0.0))
      throw std::invalid_argument(
          "OcclusionStep: gate_margin and gate_depth_coefficient must be >= 0");
    receiver_box_ = receiver->Bounds();
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(options_.gate_margin);
    receiver_box_ = Eigen::AlignedBox3d(receiver_box_.min() - grow, receiver_box_.max() + grow);
  }
  if (options_.build_reference) {
    if (receiver == nullptr)
      throw std::invalid_argument("OcclusionStep: a dynamic reference needs the receiver mesh");
    reference_ =
        std::make_unique<DynamicReference>(*receiver, options_.sampling, options_.reference);
  }
}

OcclusionStep::~OcclusionStep() = default;

bool OcclusionStep::UsesBoom(bool volumes_wanted) const {
  if (!options_.model_boom) return false;
  return options_.cull != CullMethod::kNone || reference_ || volumes_wanted;
}

bool OcclusionStep::NeedsLinks(bool volumes_wanted) const {
  return boom_ && UsesBoom(volumes_wanted);
}

std::vector<std::string> OcclusionStep::boom_links() const {
  return boom_ ? boom_->links() : std::vector<std::string>{};
}

OcclusionResult OcclusionStep::Process(const OcclusionInput& in) {
  OcclusionResult r;
  // Out-of-range points leave first: a corrupt cloud (coordinates of 1e20) would otherwise place
  // the centroid seed, and the reference with it, 1e19 m away. `points` are the rest;
  // `in_range[k]` is the index in in.points of points[k] when some left. Counted first, so that
  // the usual frame (every point in range) builds no index list.
  const double max_range2 = options_.max_point_range * options_.max_point_range;
  const auto within = [&](const Eigen::Vector3d& p) {
    return (p - in.left_eye).squaredNorm() <= max_range2;
  };
  r.out_of_range = static_cast<size_t>(
      std::count_if(in.points.begin(), in.points.end(), [&](const auto& p) { return !within(p); }));
  std::vector<size_t> in_range;
  std::vector<Eigen::Vector3d> kept_in_range;
  if (r.out_of_range > 0) {
    for (size_t i = 0; i < in.points.size(); ++i) {
      if (!within(in.points[i])) continue;
      in_range.push_back(i);
      kept_in_range.push_back(in.points[i]);
    }
  }
  const std::vector<Eigen::Vector3d>& points = r.out_of_range > 0 ? kept_in_range : in.points;
  PlaceBoom(in, &r);
  SplitBoomAndGate(points, in, &r);
  CullPropellers(points, in, &r);
  if (reference_) BuildReference(points, in, &r);
  if (r.out_of_range > 0) {  // indices into in.points, as promised
    for (auto* indices : {&r.kept, &r.removed}) {
      for (size_t& i : *indices) i = in_range[i];
    }
  }
  return r;
}

// The boom at this frame's link poses; without it this frame passes through unculled.
void OcclusionStep::PlaceBoom(const OcclusionInput& in, OcclusionResult* r) {
  if (!UsesBoom(in.volumes_wanted)) return;  // the cloud passes through as configured
  if (!boom_) {
    r->cull_error = boom_error_;
  } else if (const std::string missing = MissingLink(boom_->links(), in.T_tanker_links);
             !missing.empty()) {
    r->cull_error =
        in.links_error.empty() ? "no pose for boom link '" + missing + "'" : in.links_error;
  } else {
    try {
      r->volumes_rebuilt = boom_->Update(in.T_tanker_links, in.left_eye, in.right_eye);
      r->boom_placed = true;
    } catch (const std::exception& e) {
      r->cull_error = e.what();
    }
  }
}

// Each point boom (removed) or kept; with gate_receiver and an estimate, points outside its
// grown receiver box are gated out. Boom points stay boom points (shown as such).
void OcclusionStep::SplitBoomAndGate(const std::vector<Eigen::Vector3d>& points,
                                     const OcclusionInput& in, OcclusionResult* r) {
  std::vector<bool> is_boom(points.size(), false);
  if (r->boom_placed) is_boom = boom_->Cull(points, options_.cull);
  const bool gate = options_.gate_receiver && in.T_tanker_receiver_predicted;
  const Eigen::Isometry3d T_receiver_tanker =
      gate ? in.T_tanker_receiver_predicted->inverse() : Eigen::Isometry3d::Identity();
  const Eigen::Vector3d eye_in_receiver = T_receiver_tanker * in.left_eye;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_boom[i] && gate &&
        !InGate(receiver_box_, eye_in_receiver, T_receiver_tanker * points[i],
                options_.gate_depth_coefficient * (points[i] - in.left_eye).squaredNorm())) {
      ++r->gated;
      continue;
    }
    (is_boom[i] ? r->removed : r->kept).push_back(i);
  }
}

// The propellers at the estimate's pose (not the seed's: it knows no attitude).
void OcclusionStep::CullPropellers(const std::vector<Eigen::Vector3d>& points,
                                   const OcclusionInput& in, OcclusionResult* r) const {
  if (!options_.cull_propellers || !in.T_tanker_receiver_predicted || options_.propellers.empty())
    return;
  std::vector<PropellerDisc> discs = options_.propellers;
  for (PropellerDisc& d : discs) {
    d.hub = *in.T_tanker_receiver_predicted * d.hub;
    d.axis = in.T_tanker_receiver_predicted->linear() * d.axis.normalized();
  }
  std::vector<size_t> kept;
  for (const size_t i : r->kept) {
    const bool on = OnPropeller(in.left_eye, points[i], discs, options_.propeller_margin,
                                options_.propeller_depth_margin);
    (on ? r->removed : kept).push_back(i);
    r->propeller_points += on;
  }
  r->kept = std::move(kept);
}

// The dynamic reference at the predicted pose: the estimate's, else the centroid seed of the
// kept points.
void OcclusionStep::BuildReference(const std::vector<Eigen::Vector3d>& points,
                                   const OcclusionInput& in, OcclusionResult* r) {
  std::optional<Eigen::Isometry3d> T_tanker_receiver = in.T_tanker_receiver_predicted;
  if (!T_tanker_receiver && !r->kept.empty()) {
    std::vector<Eigen::Vector3d> kept_points;
    for (const size_t i : r->kept) kept_points.push_back(points[i]);
    if (options_.seed_points == aar_geometry::SeedPoints::kDensestBall && receiver_radius_ > 0.0)
      kept_points = aar_geometry::DensestBall(kept_points, receiver_radius_);
    T_tanker_receiver = aar_geometry::CentroidSeed(kept_points, {Eigen::Vector3d::Zero()});
  }
  try {
    if (!T_tanker_receiver) throw std::runtime_error("no predicted pose: no estimate, no points");
    r->T_tanker_receiver = *T_tanker_receiver;
    r->reference = r->boom_placed
                       ? reference_->Build(*T_tanker_receiver, *boom_)
                       : reference_->Build(*T_tanker_receiver, in.left_eye, in.right_eye);
    r->has_reference = true;
  } catch (const std::exception& e) {
    r->reference_error = e.what();
    r->reference = DynamicReferenceResult{};
  }
}

}  // namespace aar_occlusion
