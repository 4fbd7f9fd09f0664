#include "aar_occlusion/ros/conversions.h"

#include <cstring>

namespace aar_occlusion {
namespace {

// 0x00RRGGBB per class: both red, left only cyan, right only blue, neither green.
const uint32_t kClassColours[4] = {0xff0000, 0x00ffff, 0x0000ff, 0x00ff00};

}  // namespace

sensor_msgs::PointCloud2 ToCloud(const DynamicReferenceResult& reference,
                                 const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  const char* names[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (uint32_t k = 0; k < 6; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  sensor_msgs::PointField visibility;
  visibility.name = "visibility";
  visibility.offset = 24;
  visibility.datatype = sensor_msgs::PointField::UINT8;
  visibility.count = 1;
  msg.fields.push_back(visibility);
  sensor_msgs::PointField rgb;  // rviz's RGB8 colouring, as the thesis's Fig. 17
  rgb.name = "rgb";
  rgb.offset = 28;
  rgb.datatype = sensor_msgs::PointField::FLOAT32;
  rgb.count = 1;
  msg.fields.push_back(rgb);
  msg.point_step = 32;
  msg.height = 1;
  msg.width = static_cast<uint32_t>(reference.cloud.size());
  msg.row_step = msg.point_step * msg.width;
  msg.is_dense = true;
  msg.data.assign(msg.row_step, 0);
  for (size_t i = 0; i < reference.cloud.size(); ++i) {
    uint8_t* p = &msg.data[i * msg.point_step];
    const Eigen::Vector3f point = reference.cloud.points[i].cast<float>();
    const Eigen::Vector3f normal = reference.cloud.normals[i].cast<float>();
    std::memcpy(p, point.data(), 12);
    std::memcpy(p + 12, normal.data(), 12);
    p[24] = static_cast<uint8_t>(reference.classes[i]);
    std::memcpy(p + 28, &kClassColours[static_cast<int>(reference.classes[i])], 4);
  }
  return msg;
}

visualization_msgs::MarkerArray ShadowMarkers(const BoomOcclusion& boom,
                                              const std_msgs::Header& header, double length) {
  visualization_msgs::MarkerArray markers;
  for (int e = 0; e < 2; ++e) {
    for (size_t part = 0; part < boom.parts().size(); ++part) {
      const Eigen::Isometry3d& T = boom.T_tanker_part(part);
      const aar_geometry::TriangleMesh volume = ShadowVolumeMesh(
          boom.parts()[part].mesh, boom.view(e, part), T.inverse() * boom.eye(e), length);
      visualization_msgs::Marker m;
      m.header = header;
      m.ns = e == 0 ? "left" : "right";
      m.id = static_cast<int>(part);
      m.type = visualization_msgs::Marker::TRIANGLE_LIST;
      m.action = visualization_msgs::Marker::ADD;
      m.pose.orientation.w = 1.0;
      m.scale.x = m.scale.y = m.scale.z = 1.0;
      // Left blue, right orange, both see-through.
      m.color.r = e == 0 ? 0.2f : 1.0f;
      m.color.g = e == 0 ? 0.4f : 0.5f;
      m.color.b = e == 0 ? 1.0f : 0.1f;
      m.color.a = 0.25f;
      for (const auto& t : volume.triangles) {
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d v = T * volume.vertices[t[k]];
          geometry_msgs::Point p;
          p.x = v.x();
          p.y = v.y();
          p.z = v.z();
          m.points.push_back(p);
        }
      }
      markers.markers.push_back(m);
    }
  }
  return markers;
}

}  // namespace aar_occlusion
