#pragma once

#include <cstdint>
#include <vector>

#include <aar_geometry/triangle_mesh.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace aar_alignment {

// A rectified pinhole camera (OpenCV's convention: pixel (u, v) = (fx X/Z + cx, fy Y/Z + cy) in
// the optical frame, integer values at pixel centres) and where it sits on the tanker.
struct PinholeCamera {
  int width = 0;   // [px]
  int height = 0;  // [px]
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  Eigen::Isometry3d T_tanker_optical = Eigen::Isometry3d::Identity();

  // Pixel of a point in the optical frame (z > 0).
  Eigen::Vector2d Project(const Eigen::Vector3d& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
};

// The projected mesh as a mask: image pixel (u, v) is mask pixel ((u, v) - origin) * scale.
struct SilhouetteMask {
  cv::Mat image;  // CV_8U, 1 on the receiver; empty when nothing of it is near the image
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // [px]
  double scale = 1.0;                                // mask pixels per image pixel

  bool At(const Eigen::Vector2d& pixel) const;
};

// One point of the receiver's projected outline: a point of the mesh on a silhouette edge that
// separates the receiver's image from what lies around it.
struct ContourPoint {
  Eigen::Vector3d body;    // [m] receiver frame
  Eigen::Vector2d pixel;   // [px] where it projects
  Eigen::Vector2d normal;  // unit, in the image, pointing out of the receiver's image
  // The receiver's image along the line through the point: profile[i] is 1 where the projected
  // mesh covers x = i - profile.size() / 2 + 0.5 [px] along the normal (inside negative), else 0.
  // Next to the point it is the exact step at x = 0; further out it is read off the mask, so it
  // knows a wing seen edge-on is a few pixels thick and where other parts of the receiver lie.
  std::vector<uint8_t> profile;
};

// The receiver mesh prepared for outlines: welded, with each edge's two triangles. Per pose and
// camera it finds the silhouette edges (between a triangle facing the camera and one facing away,
// or open), samples them evenly in the image, and keeps the samples on the outer outline: those
// with the receiver's image on one side and nothing of it on the other, judged on a mask of the
// projected mesh drawn at a resolution of about `mask_size` pixels across.
class OutlineModel {
 public:
  // Throws std::invalid_argument for an empty or malformed mesh.
  explicit OutlineModel(const aar_geometry::TriangleMesh& receiver);

  // About `count` outline points, evenly spread along the outline, of the receiver at
  // T_tanker_receiver seen by `camera`, each with its profile `profile_half_length` [px] either
  // side. Points outside the image are kept (the caller's lines see nothing there). Empty when
  // any vertex is behind or within 0.1 m of the camera's plane.
  // The mask is about `mask_size` pixels across, at most `mask_max_scale` mask pixels per image
  // pixel.
  std::vector<ContourPoint> Contour(const PinholeCamera& camera,
                                    const Eigen::Isometry3d& T_tanker_receiver, int count,
                                    int profile_half_length = 0, int mask_size = 320,
                                    double mask_max_scale = 4.0) const;

  // The receiver at T_tanker_receiver seen by `camera` as a mask about `size` pixels across (its
  // part within 64 px of the image), at most `max_scale` mask pixels per image pixel. Empty when
  // any vertex is behind or within 0.1 m of the camera's plane.
  SilhouetteMask Silhouette(const PinholeCamera& camera, const Eigen::Isometry3d& T_tanker_receiver,
                            int size, double max_scale = 4.0) const;

  const aar_geometry::TriangleMesh& mesh() const { return mesh_; }
  // [m] the farthest vertex from the receiver's origin.
  double radius() const { return radius_; }

 private:
  // Vertices in the camera's optical frame and their pixels; false when one is too near.
  bool Project(const PinholeCamera& camera, const Eigen::Isometry3d& T_tanker_receiver,
               std::vector<Eigen::Vector3d>& optical, std::vector<Eigen::Vector2d>& pixels) const;

  // Per triangle, whether it faces the camera (vertices in the optical frame).
  std::vector<char> Facing(const std::vector<Eigen::Vector3d>& optical) const;

  struct MeshEdge {
    int v0, v1;  // vertex indices
    int t0, t1;  // the triangles on either side; t1 = -1 for an open edge
  };
  aar_geometry::TriangleMesh mesh_;  // welded
  std::vector<MeshEdge> edges_;
  double radius_ = 0.0;  // [m]
};

}  // namespace aar_alignment
