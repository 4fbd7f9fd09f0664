#include "aar_ros_common/markers.h"

#include <filesystem>

namespace aar_ros_common {

std_msgs::ColorRGBA Rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker MeshMarker(const std::string& frame_id, const std::string& ns,
                                      const std::string& mesh_path,
                                      const std_msgs::ColorRGBA& colour,
                                      const Eigen::Isometry3d& T_frame_mesh, double scale) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.ns = ns;
  m.type = visualization_msgs::Marker::MESH_RESOURCE;
  m.mesh_resource = "file://" + std::filesystem::absolute(mesh_path).string();
  const Eigen::Quaterniond q(T_frame_mesh.linear());
  m.pose.position.x = T_frame_mesh.translation().x();
  m.pose.position.y = T_frame_mesh.translation().y();
  m.pose.position.z = T_frame_mesh.translation().z();
  m.pose.orientation.w = q.w();
  m.pose.orientation.x = q.x();
  m.pose.orientation.y = q.y();
  m.pose.orientation.z = q.z();
  m.scale.x = m.scale.y = m.scale.z = scale;
  m.color = colour;
  m.frame_locked = true;
  return m;
}

visualization_msgs::Marker TriangleListMarker(const std_msgs::Header& header, const std::string& ns,
                                              int id, const std::vector<Eigen::Vector3d>& vertices,
                                              const std_msgs::ColorRGBA& colour) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color = colour;
  m.points.reserve(vertices.size());
  for (const Eigen::Vector3d& v : vertices) {
    geometry_msgs::Point p;
    p.x = v.x();
    p.y = v.y();
    p.z = v.z();
    m.points.push_back(p);
  }
  return m;
}

}  // namespace aar_ros_common
