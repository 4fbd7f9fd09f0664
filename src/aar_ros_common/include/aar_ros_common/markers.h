#pragma once

#include <string>
#include <vector>

#include <std_msgs/ColorRGBA.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/Marker.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace aar_ros_common {

std_msgs::ColorRGBA Rgba(float r, float g, float b, float a);

// A mesh file (any format rviz reads) drawn in `frame_id`, locked to that frame so that it
// follows tf: scaled by `scale`, then placed by T_frame_mesh (a receiver description's scale and
// mesh_to_body).
visualization_msgs::Marker MeshMarker(
    const std::string& frame_id, const std::string& ns, const std::string& mesh_path,
    const std_msgs::ColorRGBA& colour,
    const Eigen::Isometry3d& T_frame_mesh = Eigen::Isometry3d::Identity(), double scale = 1.0);

// Triangles given as consecutive vertex triples in the header's frame [m].
visualization_msgs::Marker TriangleListMarker(const std_msgs::Header& header, const std::string& ns,
                                              int id, const std::vector<Eigen::Vector3d>& vertices,
                                              const std_msgs::ColorRGBA& colour);

}  // namespace aar_ros_common
