#include "aar_registration/registrar.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>

namespace aar_registration {

Registrar::Registrar(const RegistrarOptions& options)
    : options_(options), icp_(options.icp), tracker_(options.tracker) {
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
  icp_.SetTarget(cloud.points, cloud.normals);
  return cloud.size();
}

void Registrar::SetReference(std::vector<Eigen::Vector3d> points,
                             std::vector<Eigen::Vector3d> normals) {
  icp_ = Icp(options_.icp);  // no stale target, whatever happens below
  reference_points_.clear();
  if (points.size() < 10) {
    throw std::invalid_argument("reference cloud has " + std::to_string(points.size()) +
                                " usable points");
  }
  icp_.SetTarget(points, std::move(normals));  // point-to-plane refuses a target without normals
  reference_points_ = std::move(points);
}

TrackPrediction Registrar::Predict(double stamp_s) const {
  return options_.track ? tracker_.Predict(stamp_s) : TrackPrediction{};
}

void Registrar::Align(const std::vector<Eigen::Vector3d>& sensed, const Eigen::Isometry3d& seed,
                      RegistrarResult& out) const {
  out.icp = icp_.Align(sensed, seed.inverse());
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

RegistrarResult Registrar::Register(const std::vector<Eigen::Vector3d>& all_sensed,
                                    double stamp_s) {
  const auto start = std::chrono::steady_clock::now();
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
    std::ostringstream gate;
    if (out.registered && out.icp.fitness < options_.gate.min_fitness)
      gate << "fitness " << out.icp.fitness << " < " << options_.gate.min_fitness;
    else if (out.registered && out.icp.rms > options_.gate.max_rms)
      gate << "RMS " << out.icp.rms << " m > " << options_.gate.max_rms << " m";
    else if (out.registered && out.icp.degenerate)
      gate << "the reference leaves a motion unconstrained";
    if (!out.registered)
      out.track = tracker_.Reject(stamp_s, out.error);
    else if (!gate.str().empty())
      out.track = tracker_.Reject(stamp_s, "registration rejected: " + gate.str());
    else
      out.track =
          tracker_.Update(stamp_s, out.T_tanker_receiver_registered,
                          CovarianceInTanker(out.icp.covariance, out.T_tanker_receiver_registered));
    const TrackPrediction& filtered = out.track.filtered;
    out.valid = filtered.valid;
    out.T_tanker_receiver = filtered.T_tanker_receiver;
    out.covariance = filtered.covariance;
    out.velocity = filtered.velocity;
    out.angular_velocity = filtered.angular_velocity;
    if (!out.valid && out.error.empty()) out.error = out.track.reason;
  }
  out.registration_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace aar_registration
