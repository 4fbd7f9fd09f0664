#include "aar_ros_common/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <sensor_msgs/point_cloud2_iterator.h>  // sizeOfPointField, PointCloud2Modifier

namespace aar_ros_common {
namespace {

const sensor_msgs::PointField* Field(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const auto& f : msg.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

size_t NumPoints(const sensor_msgs::PointCloud2& msg) {
  return static_cast<size_t>(msg.width) * msg.height;
}

void CheckLayout(const sensor_msgs::PointCloud2& msg) {
  if (msg.is_bigendian)
    throw std::invalid_argument("cloud is big-endian: only little-endian clouds are read");
  if (msg.row_step < static_cast<uint64_t>(msg.width) * msg.point_step ||
      msg.data.size() != static_cast<size_t>(msg.row_step) * msg.height) {
    throw std::invalid_argument("cloud is malformed: " + std::to_string(msg.data.size()) +
                                " bytes for " + std::to_string(msg.height) + " rows of " +
                                std::to_string(msg.row_step) + " (" + std::to_string(msg.width) +
                                " points of " + std::to_string(msg.point_step) + ")");
  }
  for (const auto& f : msg.fields) {
    size_t size = 0;
    try {
      // sensor_msgs declares it in an unnamed namespace of its iterator header.
      size = static_cast<size_t>(sizeOfPointField(f.datatype));
    } catch (const std::runtime_error&) {
      throw std::invalid_argument("cloud field '" + f.name + "' has unknown type " +
                                  std::to_string(f.datatype));
    }
    if (f.offset + size * std::max<uint32_t>(f.count, 1) > msg.point_step)
      throw std::invalid_argument("cloud field '" + f.name + "' exceeds point_step");
  }
}

// Where point i starts in the data: rows may carry padding (row_step > width * point_step).
size_t PointStart(const sensor_msgs::PointCloud2& msg, size_t i) {
  return i / msg.width * msg.row_step + i % msg.width * msg.point_step;
}

// A value at a byte position, copied out: fields need not be aligned (in a 13-byte point, or
// after a uint16 field, floats are not), and a load through a cast pointer would be undefined
// (sensor_msgs' iterators do that; the point_cloud fuzz target found it).
template <typename T>
T Load(const sensor_msgs::PointCloud2& msg, size_t at) {
  T value;
  std::memcpy(&value, msg.data.data() + at, sizeof(T));
  return value;
}

template <typename T>
void Read(const sensor_msgs::PointCloud2& msg, uint32_t offset,
          const std::vector<uint32_t>& indices, std::vector<double>& out) {
  for (const uint32_t i : indices)
    out.push_back(static_cast<double>(Load<T>(msg, PointStart(msg, i) + offset)));
}

}  // namespace

bool HasField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  return Field(msg, name) != nullptr;
}

CloudPoints FromCloud(const sensor_msgs::PointCloud2& msg) {
  uint32_t offsets[3];
  for (int k = 0; k < 3; ++k) {
    const char* name = k == 0 ? "x" : k == 1 ? "y" : "z";
    const auto* f = Field(msg, name);
    if (f == nullptr || f->datatype != sensor_msgs::PointField::FLOAT32)
      throw std::invalid_argument(std::string("cloud has no float32 field '") + name + "'");
    offsets[k] = f->offset;
  }
  CheckLayout(msg);
  CloudPoints out;
  const size_t n = NumPoints(msg);
  out.points.reserve(n);
  out.indices.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t start = PointStart(msg, i);
    const float x = Load<float>(msg, start + offsets[0]), y = Load<float>(msg, start + offsets[1]),
                z = Load<float>(msg, start + offsets[2]);
    if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) {
      out.points.emplace_back(x, y, z);
      out.indices.push_back(static_cast<uint32_t>(i));
    }
  }
  return out;
}

std::vector<double> ReadField(const sensor_msgs::PointCloud2& msg, const std::string& name,
                              const std::vector<uint32_t>& indices) {
  const auto* f = Field(msg, name);
  if (f == nullptr) throw std::invalid_argument("cloud has no field '" + name + "'");
  CheckLayout(msg);
  for (const uint32_t i : indices) {
    if (i >= NumPoints(msg)) throw std::invalid_argument("point index beyond the cloud");
  }
  std::vector<double> out;
  out.reserve(indices.size());
  // Indexed by PointField's datatype constants, INT8 (1) to FLOAT64 (8); CheckLayout refused
  // any other.
  using Reader = void (*)(const sensor_msgs::PointCloud2&, uint32_t, const std::vector<uint32_t>&,
                          std::vector<double>&);
  static constexpr Reader kReaders[] = {nullptr,         &Read<int8_t>,   &Read<uint8_t>,
                                        &Read<int16_t>,  &Read<uint16_t>, &Read<int32_t>,
                                        &Read<uint32_t>, &Read<float>,    &Read<double>};
  static_assert(sensor_msgs::PointField::INT8 == 1 && sensor_msgs::PointField::FLOAT64 == 8);
  kReaders[f->datatype](msg, f->offset, indices, out);
  return out;
}

sensor_msgs::PointCloud2 SelectPoints(const sensor_msgs::PointCloud2& msg,
                                      const std::vector<uint32_t>& indices) {
  CheckLayout(msg);
  sensor_msgs::PointCloud2 out;
  out.header = msg.header;
  out.fields = msg.fields;
  out.is_bigendian = msg.is_bigendian;
  out.point_step = msg.point_step;
  out.is_dense = true;  // only finite points are selected by callers
  out.height = 1;
  sensor_msgs::PointCloud2Modifier(out).resize(indices.size());  // height 1, row_step, data
  for (size_t k = 0; k < indices.size(); ++k) {
    if (indices[k] >= NumPoints(msg)) throw std::invalid_argument("point index beyond the cloud");
    if (out.point_step == 0) continue;  // no bytes, and memcpy wants real pointers
    std::memcpy(out.data.data() + k * out.point_step, msg.data.data() + PointStart(msg, indices[k]),
                out.point_step);
  }
  return out;
}

}  // namespace aar_ros_common
