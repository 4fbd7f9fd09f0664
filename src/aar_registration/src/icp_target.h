// Icp's target, shared by the metrics' implementations (icp.cpp, ray_icp.cpp); not installed.
#pragma once

#include <memory>
#include <vector>

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

// kStereoRays: Icp::Align for that metric (ray_icp.cpp).
RegistrationResult AlignAlongRays(const Icp::Target& target, const IcpOptions& options,
                                  const std::vector<Eigen::Vector3d>& source,
                                  const Eigen::Isometry3d& guess, const Eigen::Vector3d& eye);

}  // namespace aar_registration
