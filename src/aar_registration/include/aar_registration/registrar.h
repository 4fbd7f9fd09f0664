#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/triangle_mesh.h>
#include <Eigen/Geometry>

#include "aar_registration/icp.h"

namespace aar_registration {

// The reference model registered to: a static one built once from the receiver mesh (thesis:
// shelled, or its wings and nose), or one given per frame (the occlusion stage's dynamic model).
enum class ReferenceKind { kShelled, kWingsNose, kDense, kTopic };
// Thesis: centroid of the sensed points with the tanker's orientation; or the previous estimate.
enum class SeedMode { kCentroid, kPrevious };

struct RegistrarOptions {
  ReferenceKind reference = ReferenceKind::kShelled;
  aar_geometry::ReferenceModelOptions sampling;
  Eigen::Isometry3d T_tanker_receiver_nominal = Eigen::Isometry3d::Identity();  // shelling pose
  IcpOptions icp;
  SeedMode seed = SeedMode::kCentroid;
  double previous_max_age = 1.0;  // [s] older previous estimates are not used as seeds
};

struct RegistrarResult {
  bool valid = false;  // a pose; otherwise `error` says why not (a miss)
  std::string error;
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  RegistrationResult icp;    // converged, iterations, rms, fitness, correspondences
  size_t sensed_points = 0;  // registered (finite, in the tanker frame)
  size_t reference_points = 0;
  double registration_ms = 0.0;  // [ms] ICP alone
};

// Registers each sensed cloud against the receiver's reference model: owns the reference, the
// seed policy (centroid or previous estimate) and ICP. One per node; not thread-safe.
class Registrar {
 public:
  explicit Registrar(const RegistrarOptions& options);  // throws std::invalid_argument

  // The static reference (options.reference other than kTopic): `receiver` sampled, then shelled
  // as seen from `eyes_in_tanker` (the cameras) at the nominal pose unless kDense. Returns its
  // size. Throws std::runtime_error when fewer than 100 points remain.
  size_t BuildStaticReference(const aar_geometry::TriangleMesh& receiver,
                              const std::vector<Eigen::Vector3d>& eyes_in_tanker);

  // This frame's reference (receiver frame), normals optional (point-to-plane needs them).
  // Throws std::invalid_argument for fewer than 10 points or a target ICP refuses; the previous
  // reference is gone either way, so a frame never registers to a stale one.
  void SetReference(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);
  bool has_reference() const { return icp_.has_target(); }

  // Sensed points in the tanker frame at `stamp_s` [s]. Never throws: a frame without a pose
  // comes back with valid = false and the reason.
  RegistrarResult Register(const std::vector<Eigen::Vector3d>& sensed_in_tanker, double stamp_s);

  const RegistrarOptions& options() const { return options_; }

 private:
  RegistrarOptions options_;
  Icp icp_;
  std::vector<Eigen::Vector3d> reference_points_;                 // receiver frame
  std::optional<std::pair<double, Eigen::Isometry3d>> previous_;  // stamp [s], T_tanker_receiver
};

}  // namespace aar_registration
