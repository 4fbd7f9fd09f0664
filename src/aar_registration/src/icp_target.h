// Icp's target, shared by the metrics' implementations (icp.cpp, ray_icp.cpp); not installed.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Eigenvalues>

#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <nanoflann.hpp>

#include "aar_registration/icp.h"

namespace aar_registration {

struct PointSet {
  std::vector<Eigen::Vector3d> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return pts[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>,
                                                   PointSet, 3>;

// PCL keeps its iteration count protected.
struct Gicp : pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> {
  int iterations() const { return nr_iterations_; }
};

struct Icp::Target {
  PointSet set;
  std::vector<Eigen::Vector3d> normals;
  std::unique_ptr<KdTree> tree;
  std::unique_ptr<Gicp> gicp;  // kGeneralizedPcl: target covariances computed once, then reused
};

// Whether a 6x6 normal matrix with these eigenvalues (ascending) constrains every rigid motion: a
// plane or a line leaves motions free (their eigenvalues near 0), which LDLT would quietly zero.
inline bool WellConditioned(const Vector6d& eigenvalues) {
  return eigenvalues(0) > 1e-9 * eigenvalues(5);
}

// The linearised step of the plane metrics: A x = b solved for a small motion x = (w, t), the
// rotation vector w and the translation t, as a rigid transform; none when A leaves a motion free.
inline std::optional<Eigen::Isometry3d> SmallMotion(const Matrix6d& A, const Vector6d& b) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(A, Eigen::EigenvaluesOnly);
  if (!WellConditioned(eigen.eigenvalues())) return std::nullopt;
  const Vector6d x = A.ldlt().solve(b);
  const Eigen::Vector3d w = x.head<3>();
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() =
      (w.norm() > 0.0 ? Eigen::AngleAxisd(w.norm(), w.normalized()) : Eigen::AngleAxisd::Identity())
          .toRotationMatrix();
  step.translation() = x.tail<3>();
  return step;
}

// kStereoRays: Icp::Align for that metric (ray_icp.cpp).
RegistrationResult AlignAlongRays(const Icp::Target& target, const IcpOptions& options,
                                  const std::vector<Eigen::Vector3d>& source,
                                  const Eigen::Isometry3d& guess, const Eigen::Vector3d& eye);

}  // namespace aar_registration
