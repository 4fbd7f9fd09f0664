#include "aar_occlusion/ros/conversions.h"

#include <cstring>

#include <aar_ros_common/markers.h>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace aar_occlusion {
namespace {

// 0x00RRGGBB per class: both red, left only cyan, right only blue, neither green.
const uint32_t kClassColours[4] = {0xff0000, 0x00ffff, 0x0000ff, 0x00ff00};

}  // namespace

sensor_msgs::PointCloud2 ToCloud(const DynamicReferenceResult& reference,
                                 const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  msg.is_dense = true;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  // rgb: rviz's RGB8 colouring, as the thesis's Fig. 17.
  modifier.setPointCloud2Fields(
      8, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "normal_x", 1, sensor_msgs::PointField::FLOAT32, "normal_y",
      1, sensor_msgs::PointField::FLOAT32, "normal_z", 1, sensor_msgs::PointField::FLOAT32, "rgb",
      1, sensor_msgs::PointField::FLOAT32, "visibility", 1, sensor_msgs::PointField::UINT8);
  // 29 bytes of fields padded to 32: the iterators below write floats through cast pointers,
  // undefined behaviour (and slow) at the unaligned offsets of a 29-byte point (UBSan found it).
  msg.point_step = 32;
  modifier.resize(reference.cloud.size());
  // sensor_msgs' iterators start at data.front(): undefined behaviour on an empty cloud.
  if (reference.cloud.size() == 0) return msg;
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), nx(msg, "normal_x");
  sensor_msgs::PointCloud2Iterator<uint8_t> rgb(msg, "rgb"), visibility(msg, "visibility");
  for (size_t i = 0; i < reference.cloud.size(); ++i, ++x, ++nx, ++rgb, ++visibility) {
    const Eigen::Vector3f point = reference.cloud.points[i].cast<float>();
    const Eigen::Vector3f normal = reference.cloud.normals[i].cast<float>();
    for (int k = 0; k < 3; ++k) {
      x[k] = point[k];  // x, y, z and normal_x, normal_y, normal_z are consecutive
      nx[k] = normal[k];
    }
    const int c = static_cast<int>(reference.classes[i]);
    *visibility = static_cast<uint8_t>(c);
    std::memcpy(&rgb[0], &kClassColours[c], 4);
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
      std::vector<Eigen::Vector3d> vertices;
      for (const auto& t : volume.triangles) {
        for (int k = 0; k < 3; ++k) vertices.push_back(T * volume.vertices[t[k]]);
      }
      // Left blue, right orange, both see-through.
      markers.markers.push_back(aar_ros_common::TriangleListMarker(
          header, e == 0 ? "left" : "right", static_cast<int>(part), vertices,
          e == 0 ? aar_ros_common::Rgba(0.2f, 0.4f, 1.0f, 0.25f)
                 : aar_ros_common::Rgba(1.0f, 0.5f, 0.1f, 0.25f)));
    }
  }
  return markers;
}

}  // namespace aar_occlusion
