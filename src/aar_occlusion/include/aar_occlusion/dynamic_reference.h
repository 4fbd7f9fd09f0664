#pragma once

#include <memory>
#include <vector>

#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/triangle_mesh.h>

#include "aar_occlusion/boom.h"

namespace aar_occlusion {

struct DynamicReferenceOptions {
  // [m] self-occlusion is recomputed when an eye, seen from the receiver, has moved farther than
  // this since the last computation; 0 recomputes it every frame.
  double reshell_distance = 0.0;
};

// The reference model of one frame (thesis 3.8): the samples some eye sees past the receiver
// itself, each with its class through the boom's shadow volumes.
struct DynamicReferenceResult {
  aar_geometry::ReferenceCloud cloud;  // receiver frame
  std::vector<Visibility> classes;     // per point of cloud
  size_t both = 0;                     // points seen by both eyes: what ICP registers to
  bool reshelled = false;              // self-occlusion recomputed this frame
};

class DynamicReference {
 public:
  // Samples `receiver` (receiver frame) with `sampling`, whose visibility_tolerance is also the
  // self-occlusion's: hits closer than it to a sample do not hide it. Throws
  // std::invalid_argument when the sampling gives no points.
  DynamicReference(const aar_geometry::TriangleMesh& receiver,
                   const aar_geometry::ReferenceModelOptions& sampling,
                   const DynamicReferenceOptions& options = {});
  ~DynamicReference();

  // At the predicted pose, with the eyes and shadow volumes of `boom` (which must be ready()).
  // A point is hidden from an eye when it faces away, the receiver hides it, or it lies in that
  // eye's boom shadow.
  DynamicReferenceResult Build(const Eigen::Isometry3d& T_tanker_receiver,
                               const BoomOcclusion& boom);
  // The same without a boom: self-occlusion only, eyes [tanker frame].
  DynamicReferenceResult Build(const Eigen::Isometry3d& T_tanker_receiver,
                               const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye);

  size_t size() const { return dense_.size(); }

 private:
  DynamicReferenceResult Build(const Eigen::Isometry3d& T_tanker_receiver,
                               const Eigen::Vector3d& left_eye, const Eigen::Vector3d& right_eye,
                               const BoomOcclusion* boom);

  aar_geometry::ReferenceCloud dense_;
  double visibility_tolerance_;  // [m]
  DynamicReferenceOptions options_;
  std::unique_ptr<aar_geometry::VisibilityTester> receiver_;
  bool shelled_ = false;
  Eigen::Vector3d shelled_eyes_[2];     // receiver frame
  aar_geometry::ReferenceCloud shell_;  // samples some eye sees past the receiver itself
  std::vector<bool> self_visible_[2];   // per point of shell_
};

}  // namespace aar_occlusion
