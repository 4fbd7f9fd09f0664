#include "aar_occlusion/dynamic_reference.h"

#include <stdexcept>

namespace aar_occlusion {

DynamicReference::DynamicReference(const aar_geometry::TriangleMesh& receiver,
                                   const aar_geometry::ReferenceModelOptions& sampling,
                                   const DynamicReferenceOptions& options)
    : dense_(aar_geometry::SampleReceiver(receiver, sampling)),
      visibility_tolerance_(sampling.visibility_tolerance),
      options_(options),
      receiver_(std::make_unique<aar_geometry::VisibilityTester>(receiver)) {
  if (dense_.size() == 0) throw std::invalid_argument("DynamicReference: no reference samples");
}

DynamicReference::~DynamicReference() = default;

DynamicReferenceResult DynamicReference::Build(const Eigen::Isometry3d& T_tanker_receiver,
                                               const BoomOcclusion& boom) {
  if (!boom.ready()) throw std::logic_error("DynamicReference::Build: boom volumes not built");
  return Build(T_tanker_receiver, boom.eye(0), boom.eye(1), &boom);
}

DynamicReferenceResult DynamicReference::Build(const Eigen::Isometry3d& T_tanker_receiver,
                                               const Eigen::Vector3d& left_eye,
                                               const Eigen::Vector3d& right_eye) {
  return Build(T_tanker_receiver, left_eye, right_eye, nullptr);
}

DynamicReferenceResult DynamicReference::Build(const Eigen::Isometry3d& T_tanker_receiver,
                                               const Eigen::Vector3d& left_eye,
                                               const Eigen::Vector3d& right_eye,
                                               const BoomOcclusion* boom) {
  if (!T_tanker_receiver.matrix().allFinite())
    throw std::invalid_argument("predicted receiver pose is not finite");
  const Eigen::Isometry3d T_receiver_tanker = T_tanker_receiver.inverse();
  const Eigen::Vector3d eyes[2] = {T_receiver_tanker * left_eye, T_receiver_tanker * right_eye};

  DynamicReferenceResult result;
  bool moved = !shelled_;
  for (int e = 0; e < 2 && !moved; ++e)
    moved = (eyes[e] - shelled_eyes_[e]).norm() > options_.reshell_distance;
  if (moved) {
    std::vector<bool> seen[2];
    for (int e = 0; e < 2; ++e) {
      seen[e] = receiver_->Visible(dense_.points, dense_.normals, eyes[e], visibility_tolerance_);
      shelled_eyes_[e] = eyes[e];
    }
    std::vector<bool> keep(dense_.size(), false);
    for (int e = 0; e < 2; ++e) self_visible_[e].clear();
    for (size_t i = 0; i < dense_.size(); ++i) {
      keep[i] = seen[0][i] || seen[1][i];
      if (!keep[i]) continue;
      for (int e = 0; e < 2; ++e) self_visible_[e].push_back(seen[e][i]);
    }
    shell_ = dense_.Subset(keep);  // what some eye sees past the receiver itself
    shelled_ = true;
    result.reshelled = true;
  }

  result.cloud = shell_;
  result.classes.reserve(shell_.size());
  for (size_t i = 0; i < shell_.size(); ++i) {
    bool seen[2] = {self_visible_[0][i], self_visible_[1][i]};
    if (boom != nullptr) {
      const Eigen::Vector3d p = T_tanker_receiver * shell_.points[i];
      for (int e = 0; e < 2; ++e) seen[e] = seen[e] && !boom->Hidden(p, e);
    }
    const Visibility v = seen[0] && seen[1] ? Visibility::kBoth
                         : seen[0]          ? Visibility::kLeftOnly
                         : seen[1]          ? Visibility::kRightOnly
                                            : Visibility::kNeither;
    result.both += v == Visibility::kBoth;
    result.classes.push_back(v);
  }
  return result;
}

}  // namespace aar_occlusion
