#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <sensor_msgs/PointCloud2.h>
#include <Eigen/Core>

namespace aar_ros_common {

// The finite points of a cloud and where each sits in it (row * width + column).
struct CloudPoints {
  std::vector<Eigen::Vector3d> points;  // [m], the cloud's frame
  std::vector<uint32_t> indices;
};

// Read through sensor_msgs' iterators. Throws std::invalid_argument if the cloud has no float32
// x, y, z, is big-endian, or its layout does not hold together (a field beyond point_step, data
// size against rows).
CloudPoints FromCloud(const sensor_msgs::PointCloud2& msg);

bool HasField(const sensor_msgs::PointCloud2& msg, const std::string& name);

// The values of a numeric field at the given point indices, as double. Throws
// std::invalid_argument naming a missing field, an unsupported type or an index beyond the cloud.
std::vector<double> ReadField(const sensor_msgs::PointCloud2& msg, const std::string& name,
                              const std::vector<uint32_t>& indices);

// The points at `indices`, every field kept, as an unorganized dense cloud with msg's header.
sensor_msgs::PointCloud2 SelectPoints(const sensor_msgs::PointCloud2& msg,
                                      const std::vector<uint32_t>& indices);

}  // namespace aar_ros_common
