#include "aar_registration/registrar.h"

#include <chrono>
#include <stdexcept>

namespace aar_registration {

Registrar::Registrar(const RegistrarOptions& options) : options_(options), icp_(options.icp) {}

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
      cloud = cloud.Select({"left_wing", "right_wing", "nose"});
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

RegistrarResult Registrar::Register(const std::vector<Eigen::Vector3d>& sensed, double stamp_s) {
  RegistrarResult out;
  out.sensed_points = sensed.size();
  out.reference_points = reference_points_.size();
  try {
    if (!icp_.has_target()) throw std::runtime_error("no reference model yet");
    if (sensed.size() < static_cast<size_t>(options_.icp.min_correspondences)) {
      throw std::invalid_argument("cloud has " + std::to_string(sensed.size()) +
                                  " finite points, too few to register");
    }
    Eigen::Isometry3d seed =
        aar_geometry::CentroidSeed(sensed, reference_points_);  // T_tanker_receiver
    if (options_.seed == SeedMode::kPrevious && previous_ &&
        stamp_s - previous_->first <= options_.previous_max_age && stamp_s >= previous_->first) {
      seed = previous_->second;
    }
    const auto start = std::chrono::steady_clock::now();
    out.icp = icp_.Align(sensed, seed.inverse());
    out.registration_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (out.icp.correspondences < options_.icp.min_correspondences) {
      throw std::runtime_error("only " + std::to_string(out.icp.correspondences) + " of " +
                               std::to_string(sensed.size()) + " points within " +
                               std::to_string(options_.icp.max_correspondence_distance) +
                               " m of the reference: no pose");
    }
    out.T_tanker_receiver = out.icp.T_target_source.inverse();
    if (!out.T_tanker_receiver.matrix().allFinite())
      throw std::runtime_error("registration gave a non-finite pose");
    if (out.icp.converged) previous_ = std::make_pair(stamp_s, out.T_tanker_receiver);
    out.valid = true;
  } catch (const std::exception& e) {
    out.valid = false;
    out.error = e.what();
  }
  return out;
}

}  // namespace aar_registration
