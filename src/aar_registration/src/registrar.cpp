#include "aar_registration/registrar.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>

#include "aar_registration/covariance_models.h"

namespace aar_registration {

void OutlineOptions::Validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("outline: " + what); };
  alignment.Validate();
  if (!(min_quality >= 0.0 && min_quality <= 1.0)) fail("min_quality must lie in [0, 1]");
  if (!(maneuver_quality >= 0.0 && maneuver_quality <= 1.0))
    fail("maneuver_quality must lie in [0, 1]");
  if (max_poor_frames < 1) fail("max_poor_frames must be at least 1");
  if (start_candidates < 1) fail("start_candidates must be at least 1");
  if (!(start_sigma_position > 0.0) || !(start_sigma_rotation > 0.0))
    fail("start_sigma_position and start_sigma_rotation must be > 0");
  if (!(disparity_sigma >= 0.0)) fail("disparity_sigma must be >= 0");
  acquisition.Validate();
  if (!(image_start_quality >= 0.0 && image_start_quality <= 1.0))
    fail("image_start_quality must lie in [0, 1]");
  if (!(partial_below >= 0.0 && partial_below <= 1.0)) fail("partial_below must lie in [0, 1]");
  if (partial_confirm < 0) fail("partial_confirm must be >= 0");
  if (!(partial_range_sigmas >= 0.0)) fail("partial_range_sigmas must be >= 0");
  if (partial_range_sigmas > 0.0 && !(disparity_sigma > 0.0))
    fail("partial_range_sigmas needs disparity_sigma (stereo's noise) > 0");
  if (partial_range_min_points < 1) fail("partial_range_min_points must be at least 1");
  if (partial_range_independent_points < 1)
    fail("partial_range_independent_points must be at least 1");
  if (partial_range_required && !(partial_range_sigmas > 0.0))
    fail("partial_range_required needs partial_range_sigmas > 0");
  if (range_all_starts && !(partial_range_sigmas > 0.0))
    fail("range_all_starts needs partial_range_sigmas > 0");
  if (!(information_floor_position > 0.0) || !(information_floor_rotation > 0.0))
    fail("information_floor_position and information_floor_rotation must be > 0");
}

Registrar::Registrar(const RegistrarOptions& options)
    : options_(options),
      icp_(options.icp),
      tracker_(options.tracker),
      integrity_(options.integrity) {
  if (options.outline.enabled && !options.track)
    throw std::invalid_argument("the outline (outline.enabled) needs tracking (track: true)");
  options.outline.Validate();
  if (options.seed == SeedMode::kPrediction && !options.track)
    throw std::invalid_argument("the prediction seed needs tracking (track: true)");
  if (options.max_sensed_points != 0 && options.max_sensed_points < options.icp.min_correspondences)
    throw std::invalid_argument(
        "max_sensed_points must be 0 (all) or at least min_correspondences");
  if (options.max_cloud_points != 0 && options.max_cloud_points < options.icp.min_correspondences)
    throw std::invalid_argument(
        "max_cloud_points must be 0 (no bound) or at least min_correspondences");
  if (!(options.gate.min_fitness >= 0.0 && options.gate.min_fitness <= 1.0) ||
      !(options.gate.max_rms > 0.0))
    throw std::invalid_argument("gate: min_fitness must be in [0, 1] and max_rms > 0");
  if (!(options.persistent_error.pixel_sigma >= 0.0))
    throw std::invalid_argument("persistent_error: pixel_sigma must be >= 0");
}

size_t Registrar::BuildStaticReference(const aar_geometry::TriangleMesh& receiver,
                                       const std::vector<Eigen::Vector3d>& eyes_in_tanker) {
  aar_geometry::ReferenceCloud cloud = aar_geometry::SampleReceiver(receiver, options_.sampling);
  if (options_.reference != ReferenceKind::kDense) {
    // Shelled as the cameras see the receiver at the nominal pose.
    std::vector<Eigen::Vector3d> eyes;
    for (const auto& eye : eyes_in_tanker)
      eyes.push_back(options_.T_tanker_receiver_nominal.inverse() * eye);
    cloud = aar_geometry::Shell(cloud, aar_geometry::VisibilityTester(receiver), eyes,
                                options_.sampling.visibility_tolerance);
    if (options_.reference == ReferenceKind::kWingsNose)
      cloud = cloud.Select(options_.static_parts);
  }
  if (cloud.size() < 100)
    throw std::runtime_error("reference model has only " + std::to_string(cloud.size()) +
                             " points");
  reference_points_ = cloud.points;
  reference_normals_ = cloud.normals;
  icp_.SetTarget(cloud.points, cloud.normals);
  return cloud.size();
}

bool Registrar::SetReference(std::vector<Eigen::Vector3d> points,
                             std::vector<Eigen::Vector3d> normals) {
  if (icp_.has_target() && points == reference_points_ && normals == reference_normals_)
    return false;            // the same reference: its k-d tree stays
  icp_ = Icp(options_.icp);  // no stale target, whatever happens below
  reference_points_.clear();
  reference_normals_.clear();
  if (points.size() < 10) {
    throw std::invalid_argument("reference cloud has " + std::to_string(points.size()) +
                                " usable points");
  }
  icp_.SetTarget(points, normals);  // point-to-plane refuses a target without normals
  reference_points_ = std::move(points);
  reference_normals_ = std::move(normals);
  return true;
}

void Registrar::SetOutlineModel(const aar_geometry::TriangleMesh& receiver) {
  aligner_ = std::make_unique<aar_alignment::OutlineAligner>(receiver, options_.outline.alignment);
  receiver_size_m_ = 2.0 * aar_geometry::HalfDiagonal(receiver.vertices);
}

TrackPrediction Registrar::Predict(double stamp_s) const {
  return options_.track ? tracker_.Predict(stamp_s) : TrackPrediction{};
}

void Registrar::Align(const std::vector<Eigen::Vector3d>& sensed, const Eigen::Isometry3d& seed,
                      RegistrarResult& out) const {
  out.icp = icp_.Align(sensed, seed.inverse(), eye_ ? &*eye_ : nullptr);
  if (out.icp.correspondences < options_.icp.min_correspondences) {
    const double gate = options_.icp.max_correspondence_distance;
    throw std::runtime_error(
        "only " + std::to_string(out.icp.correspondences) + " of " + std::to_string(sensed.size()) +
        " points " +
        (gate > 0.0 ? "within " + std::to_string(gate) + " m of the reference" : "finite") +
        ": no pose");
  }
  out.T_tanker_receiver_registered = out.icp.T_target_source.inverse();
  if (!out.T_tanker_receiver_registered.matrix().allFinite())
    throw std::runtime_error("registration gave a non-finite pose");
  out.registered = true;
}

// Inverting turns Exp(xi) T_receiver_tanker into T_tanker_receiver Exp(-xi): to first order
// dp = -R t and dtheta = -R w with xi = (w, t) and R = R_tanker_receiver.
Matrix6d CovarianceInTanker(const Matrix6d& icp_covariance,
                            const Eigen::Isometry3d& T_tanker_receiver) {
  const Eigen::Matrix3d R = T_tanker_receiver.linear();
  Matrix6d J = Matrix6d::Zero();
  J.block<3, 3>(0, 3) = -R;
  J.block<3, 3>(3, 0) = -R;
  return J * icp_covariance * J.transpose();
}

RegistrarResult Registrar::Register(const std::vector<Eigen::Vector3d>& all_sensed, double stamp_s,
                                    const OutlineFrame* outline,
                                    const Eigen::Vector3d* left_eye_in_tanker) {
  const auto start = std::chrono::steady_clock::now();
  eye_.reset();
  if (left_eye_in_tanker) eye_ = *left_eye_in_tanker;
  RegistrarResult out;
  out.tracking = options_.track;
  out.reference_points = reference_points_.size();
  const std::vector<Eigen::Vector3d>* sensed = &all_sensed;
  std::vector<Eigen::Vector3d> subset;
  size_t limit = all_sensed.size();
  if (options_.max_sensed_points > 0)
    limit = std::min(limit, static_cast<size_t>(options_.max_sensed_points));
  if (options_.max_cloud_points > 0 &&
      all_sensed.size() > static_cast<size_t>(options_.max_cloud_points)) {
    limit = std::min(limit, static_cast<size_t>(options_.max_cloud_points));
    out.cut_from_points = all_sensed.size();
  }
  if (limit < all_sensed.size()) {
    subset.reserve(limit);
    std::sample(all_sensed.begin(), all_sensed.end(), std::back_inserter(subset), limit,
                std::mt19937(options_.subsample_seed));
    sensed = &subset;
  }
  out.sensed_points = sensed->size();
  try {
    if (!icp_.has_target()) throw std::runtime_error("no reference model yet");
    if (sensed->size() < static_cast<size_t>(options_.icp.min_correspondences)) {
      throw std::invalid_argument("cloud has " + std::to_string(sensed->size()) +
                                  " finite points, too few to register");
    }
    const TrackPrediction prediction = Predict(stamp_s);
    Eigen::Isometry3d seed;  // T_tanker_receiver
    if (options_.seed == SeedMode::kPrevious && previous_ &&
        stamp_s - previous_->first <= options_.previous_max_age && stamp_s >= previous_->first) {
      seed = previous_->second;
      out.seed = SeedMode::kPrevious;
    } else if (options_.seed == SeedMode::kPrediction && prediction.valid) {
      seed = prediction.T_tanker_receiver;
      out.seed = SeedMode::kPrediction;
    } else {  // the centroids only when used: they cost a pass over both clouds
      seed = options_.seed_points == SeedPoints::kDensestBall
                 ? aar_geometry::CentroidSeed(
                       aar_geometry::DensestBall(*sensed,
                                                 aar_geometry::HalfDiagonal(reference_points_)),
                       reference_points_)
                 : aar_geometry::CentroidSeed(*sensed, reference_points_);
      out.seed = SeedMode::kCentroid;
    }
    Align(*sensed, seed, out);
    if (out.icp.converged) previous_ = std::make_pair(stamp_s, out.T_tanker_receiver_registered);
  } catch (const std::exception& e) {
    out.error = e.what();
  }

  if (!options_.track) {
    out.valid = out.registered;
    out.T_tanker_receiver = out.T_tanker_receiver_registered;
    out.covariance = CovarianceInTanker(out.icp.covariance, out.T_tanker_receiver);
  } else {
    Track(stamp_s, *sensed, outline, out);
    DropOutsideEnvelope(out);
    const TrackPrediction& filtered = out.track.filtered;
    out.valid = filtered.valid;
    out.T_tanker_receiver = filtered.T_tanker_receiver;
    out.covariance =
        filtered.covariance + PersistentCovariance(filtered.T_tanker_receiver, outline);
    out.velocity = filtered.velocity;
    out.angular_velocity = filtered.angular_velocity;
    if (!out.valid && out.error.empty()) out.error = out.track.reason;
  }
  AssessIntegrity(out);
  WatchNewTrack(*sensed, outline, out);
  out.registration_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

namespace {

std::string Quality(const aar_alignment::AlignmentResult& a) {
  if (!a.valid) return "no alignment (" + a.error + ")";
  std::ostringstream s;
  s << "outline fit " << a.quality;
  return s.str();
}

// The alignment as a pose measurement: its information (what the images alone say), with a floor
// so that directions the outline does not see get no weight.
Matrix6d MeasurementCovariance(const aar_alignment::AlignmentResult& a, const OutlineOptions& o) {
  Matrix6d information = a.information;
  information.diagonal().head<3>().array() += o.information_floor_position;
  information.diagonal().tail<3>().array() += o.information_floor_rotation;
  return information.inverse();
}

}  // namespace

Eigen::Isometry3d Registrar::StartPose(const Eigen::Isometry3d& T) const {
  const double offset = options_.fault_start_offset_m;
  if (offset == 0.0 || !(T.translation().norm() > 0.0)) return T;
  Eigen::Isometry3d moved = T;
  moved.translation() += offset * T.translation().normalized();
  return moved;
}

std::string Registrar::OutsideEnvelope(const Eigen::Isometry3d& T) const {
  return OutsideAttitudeEnvelope(T.linear(), options_.T_tanker_receiver_nominal.linear(),
                                 options_.integrity.attitude_envelope_deg);
}

void Registrar::DropOutsideEnvelope(RegistrarResult& out) {
  if (!out.track.filtered.valid) return;
  const std::string why = OutsideEnvelope(out.track.filtered.T_tanker_receiver);
  if (why.empty()) return;
  out.track = tracker_.Drop("integrity: " + why);
  if (out.outline_ran) out.outline_note = out.track.reason;
}

void Registrar::AssessIntegrity(RegistrarResult& out) {
  IntegrityInput in;
  in.valid = out.valid;
  in.T_tanker_receiver = out.T_tanker_receiver;
  in.covariance = out.covariance;
  in.tracking = out.tracking;
  in.outcome = out.track.outcome;
  in.agreeing = out.registration_fused && (!out.outline_ran || out.outline_fused);
  in.acquisition_covariance = StartCovariance();
  in.R_tanker_receiver_nominal = options_.T_tanker_receiver_nominal.linear();
  out.integrity = integrity_.Assess(in);
  if (out.valid) out.covariance = out.integrity.covariance;
}

namespace {

// The frame's images (every rig's: the further rigs' as extra views, each left then right),
// cameras and boom, with `T` as the prediction.
aar_alignment::AlignmentInput AlignmentInputOf(const OutlineFrame& frame,
                                               const Eigen::Isometry3d& T) {
  aar_alignment::AlignmentInput in;
  in.left = frame.left, in.right = frame.right;
  in.left_camera = frame.left_camera, in.right_camera = frame.right_camera;
  for (const RigImages& rig : frame.more_rigs) {
    in.extra_views.push_back({rig.left, rig.left_camera});
    in.extra_views.push_back({rig.right, rig.right_camera});
  }
  in.boom_parts_in_tanker = frame.boom_parts_in_tanker;
  in.T_tanker_receiver_predicted = T;
  return in;
}

}  // namespace

aar_alignment::AlignmentResult Registrar::AlignOutline(const OutlineFrame& frame,
                                                       const Eigen::Isometry3d& T,
                                                       const Matrix6d& covariance,
                                                       RegistrarResult& out) const {
  aar_alignment::AlignmentInput in = AlignmentInputOf(frame, T);
  in.prediction_covariance = covariance;
  out.outline = aligner_->Align(in);
  out.outline_ran = true;
  out.outline_ms += out.outline.time_ms;
  return out.outline;
}

std::string Registrar::GateFailure(const RegistrarResult& out) const {
  std::ostringstream gate;
  if (out.icp.fitness < options_.gate.min_fitness)
    gate << "fitness " << out.icp.fitness << " < " << options_.gate.min_fitness;
  else if (out.icp.rms > options_.gate.max_rms)
    gate << "RMS " << out.icp.rms << " m > " << options_.gate.max_rms << " m";
  else if (out.icp.degenerate)
    gate << "the reference leaves a motion unconstrained";
  return gate.str();
}

namespace {

// The points farther than `radius` from `centre`.
std::vector<Eigen::Vector3d> Outside(const std::vector<Eigen::Vector3d>& points,
                                     const Eigen::Vector3d& centre, double radius) {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : points)
    if ((p - centre).squaredNorm() > radius * radius) out.push_back(p);
  return out;
}

}  // namespace

void Registrar::Start(double stamp_s, const std::vector<Eigen::Vector3d>& sensed,
                      const OutlineFrame& frame, RegistrarResult& out) {
  watch_.accepted = -1;
  const double radius = aar_geometry::HalfDiagonal(reference_points_);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the reference, receiver frame
  for (const Eigen::Vector3d& p : reference_points_) centroid += p;
  centroid /= std::max<size_t>(1, reference_points_.size());
  std::vector<Eigen::Vector3d> rest = sensed;
  std::ostringstream refused;
  for (int k = 0; k < options_.outline.start_candidates; ++k) {
    if (k > 0) {  // the next seed: the densest ball outside the refused registrations'
      if (!(radius > 0.0) || rest.size() < static_cast<size_t>(options_.icp.min_correspondences))
        break;
      out.registered = false;
      try {
        Align(
            rest,
            aar_geometry::CentroidSeed(aar_geometry::DensestBall(rest, radius), reference_points_),
            out);
      } catch (const std::exception& e) {
        out.error = e.what();
      }
    }
    std::string why = out.registered ? GateFailure(out) : out.error;
    if (why.empty()) {
      const auto a = AlignOutline(frame, out.T_tanker_receiver_registered, StartCovariance(), out);
      why = a.valid && a.quality >= options_.outline.min_quality
                ? OutsideEnvelope(a.T_tanker_receiver)
                : Quality(a);
      if (why.empty()) {
        out.track = tracker_.Update(stamp_s, StartPose(a.T_tanker_receiver), a.covariance);
        out.outline_fused = true;
        out.error.clear();
        StartWatch(false);  // a start from stereo's seeds is not a partial one
        if (k > 0) {
          std::string before = refused.str();
          before.resize(before.size() - 2);
          out.outline_note =
              "started from seed " + std::to_string(k + 1) + " (refused: " + before + ")";
        }
        return;
      }
    }
    refused << "seed " << k + 1 << ": " << why << "; ";
    if (!out.registered || rest.empty()) break;  // nothing to set aside
    rest = Outside(rest, out.T_tanker_receiver_registered * centroid, radius);
  }
  std::string stereo = refused.str();
  stereo.resize(stereo.size() - 2);
  std::string why;
  if (options_.outline.image_start) {
    if (ImageStart(stamp_s, sensed, frame, out, why)) {
      out.outline_note += " (stereo's seeds refused: " + stereo + ")";
      return;
    }
    stereo += "; images alone: " + why;
  }
  out.outline_note = "start refused: " + stereo;
  out.track = tracker_.Reject(stamp_s, out.outline_note);
  out.error = out.outline_note;  // the start's reasons hold ICP's (seed 1's), and more
}

bool Registrar::ImageStart(double stamp_s, const std::vector<Eigen::Vector3d>& sensed,
                           const OutlineFrame& frame, RegistrarResult& out, std::string& why) {
  // The nominal pose gives the attitude searched at; Acquire ignores its position.
  const aar_alignment::AlignmentInput in =
      AlignmentInputOf(frame, options_.T_tanker_receiver_nominal);
  const aar_alignment::AcquisitionResult a =
      aar_alignment::Acquire(*aligner_, in, options_.outline.acquisition, sensed);
  out.outline = a.alignment;
  out.outline_ran = true;
  out.outline_ms += a.time_ms;
  if (!a.valid) {
    why = a.error;
    return false;
  }
  if (a.alignment.quality < options_.outline.image_start_quality) {
    std::ostringstream s;
    s << Quality(a.alignment) << " < image_start_quality " << options_.outline.image_start_quality;
    why = s.str();
    return false;
  }
  why = OutsideEnvelope(a.alignment.T_tanker_receiver);
  if (!why.empty()) return false;
  out.track =
      tracker_.Update(stamp_s, StartPose(a.alignment.T_tanker_receiver), a.alignment.covariance);
  out.outline_fused = true;
  out.error.clear();
  partial_share_ = aar_alignment::SeenShare(options_.outline.acquisition, a.alignment);
  const double below = options_.outline.partial_below;
  const bool partial = partial_share_ < below || below >= 1.0;  // 1: every image start
  StartWatch(partial);
  std::ostringstream s;
  s << "started from the images alone (" << Quality(a.alignment) << ", searched from " << a.range_m
    << " m)";
  out.outline_note = s.str();
  return true;
}

void Registrar::Track(double stamp_s, const std::vector<Eigen::Vector3d>& sensed,
                      const OutlineFrame* frame, RegistrarResult& out) {
  const bool outline = options_.outline.enabled && aligner_ && frame;
  const OutlineOptions& o = options_.outline;
  if (outline && tracker_.state() != TrackState::kTracking) {
    Start(stamp_s, sensed, *frame, out);
    return;
  }
  const std::string gate = out.registered ? GateFailure(out) : "";
  if (!out.registered) {
    out.track = tracker_.Reject(stamp_s, out.error);
  } else if (!gate.empty()) {
    out.track = tracker_.Reject(stamp_s, "registration rejected: " + gate);
  } else {
    const bool start = tracker_.state() != TrackState::kTracking;
    out.track = tracker_.Update(
        stamp_s,
        start ? StartPose(out.T_tanker_receiver_registered) : out.T_tanker_receiver_registered,
        IcpCovariance(out, frame));
    out.registration_fused = out.track.outcome == TrackOutcome::kAccepted;
  }
  if (!outline || tracker_.state() != TrackState::kTracking) return;
  const bool icp_rejected = out.registered && out.track.outcome == TrackOutcome::kRejected;
  // The outline from the track (after ICP's update or coast), fused with its own covariance.
  const TrackPrediction now = tracker_.Predict(stamp_s);
  if (!now.valid) return;
  const auto a = AlignOutline(*frame, now.T_tanker_receiver, now.covariance, out);
  if (a.valid && a.quality >= o.min_quality) {
    const Matrix6d R = MeasurementCovariance(a, o);
    const Eigen::Isometry3d measured =
        o.remove_prior
            ? DataOnlyMeasurement(a.T_tanker_receiver, now.T_tanker_receiver, now.covariance, R)
            : a.T_tanker_receiver;
    TrackUpdate u = tracker_.Update(stamp_s, measured, R);
    if (u.outcome == TrackOutcome::kRejected && a.quality >= o.maneuver_quality) {
      // The images say, and fit well, that the receiver is not where the track predicts it: a
      // maneuver, followed (velocity uncertainty reset) instead of coasted through.
      tracker_.Maneuver(o.start_sigma_position, o.start_sigma_rotation);
      u = tracker_.Update(stamp_s, a.T_tanker_receiver, R);
      out.outline_note = "maneuver: the outline fits away from the prediction (" + Quality(a) + ")";
    }
    out.outline_fused = u.outcome == TrackOutcome::kAccepted;
    if (out.outline_fused) {
      poor_outline_frames_ = 0;
      out.track.filtered = u.filtered;
      if (out.track.outcome != TrackOutcome::kStarted) out.track.outcome = u.outcome;
      return;
    }
    out.outline_note = "outline not fused: " + u.reason;
  } else {
    out.outline_note = "outline not fused: " + Quality(a);
  }
  if (icp_rejected) {
    // The outline does not fit at the track, but the registration the gate rejected may be
    // right: aligned from it, an outline that fits means the receiver maneuvered; the track
    // follows it instead of coasting away.
    const auto m = AlignOutline(*frame, out.T_tanker_receiver_registered, StartCovariance(), out);
    if (m.valid && m.quality >= o.maneuver_quality) {
      tracker_.Maneuver(o.start_sigma_position, o.start_sigma_rotation);
      const TrackUpdate u = tracker_.Update(stamp_s, m.T_tanker_receiver, m.covariance);
      out.outline_fused = u.outcome == TrackOutcome::kAccepted;
      out.outline_note = "maneuver: the registration's outline fits (" + Quality(m) + ")";
      if (out.outline_fused) {
        poor_outline_frames_ = 0;
        out.track.filtered = u.filtered;
        out.track.outcome = u.outcome;
        return;
      }
    }
  }
  if (++poor_outline_frames_ >= o.max_poor_frames) {
    std::ostringstream s;
    s << "integrity: the outline has not fitted for " << poor_outline_frames_
      << " frames in a row (" << Quality(a) << ")";
    poor_outline_frames_ = 0;
    out.outline_note = s.str();
    out.track = tracker_.Drop(s.str());
  }
}

}  // namespace aar_registration
