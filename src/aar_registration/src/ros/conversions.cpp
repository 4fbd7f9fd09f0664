#include "aar_registration/ros/conversions.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace aar_registration {
namespace {

const sensor_msgs::PointField* Field(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const auto& f : msg.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

size_t FieldSize(uint8_t datatype) {
  switch (datatype) {
    case sensor_msgs::PointField::INT8:
    case sensor_msgs::PointField::UINT8:
      return 1;
    case sensor_msgs::PointField::INT16:
    case sensor_msgs::PointField::UINT16:
      return 2;
    case sensor_msgs::PointField::INT32:
    case sensor_msgs::PointField::UINT32:
    case sensor_msgs::PointField::FLOAT32:
      return 4;
    case sensor_msgs::PointField::FLOAT64:
      return 8;
  }
  return 0;
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
    if (f.offset + FieldSize(f.datatype) * std::max<uint32_t>(f.count, 1) > msg.point_step)
      throw std::invalid_argument("cloud field '" + f.name + "' exceeds point_step");
  }
}

const uint8_t* PointAt(const sensor_msgs::PointCloud2& msg, uint32_t index) {
  const uint32_t row = index / msg.width, col = index % msg.width;
  return &msg.data[static_cast<size_t>(row) * msg.row_step +
                   static_cast<size_t>(col) * msg.point_step];
}

template <typename T>
double Get(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

}  // namespace

bool HasField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  return Field(msg, name) != nullptr;
}

CloudPoints FromCloud(const sensor_msgs::PointCloud2& msg) {
  uint32_t offsets[3];
  for (int k = 0; k < 3; ++k) {
    const std::string name(1, "xyz"[k]);
    const auto* f = Field(msg, name);
    if (f == nullptr || f->datatype != sensor_msgs::PointField::FLOAT32)
      throw std::invalid_argument("cloud has no float32 field '" + name + "'");
    offsets[k] = f->offset;
  }
  CheckLayout(msg);
  CloudPoints out;
  const size_t n = static_cast<size_t>(msg.width) * msg.height;
  out.points.reserve(n);
  out.indices.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    const uint8_t* point = PointAt(msg, i);
    float v[3];
    for (int k = 0; k < 3; ++k) std::memcpy(&v[k], point + offsets[k], sizeof(float));
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      out.points.emplace_back(v[0], v[1], v[2]);
      out.indices.push_back(i);
    }
  }
  return out;
}

std::vector<double> ReadField(const sensor_msgs::PointCloud2& msg, const std::string& name,
                              const std::vector<uint32_t>& indices) {
  const auto* f = Field(msg, name);
  if (f == nullptr) throw std::invalid_argument("cloud has no field '" + name + "'");
  CheckLayout(msg);
  std::vector<double> out;
  out.reserve(indices.size());
  for (const uint32_t i : indices) {
    if (i >= static_cast<size_t>(msg.width) * msg.height)
      throw std::invalid_argument("point index beyond the cloud");
    const uint8_t* p = PointAt(msg, i) + f->offset;
    switch (f->datatype) {
      case sensor_msgs::PointField::INT8:
        out.push_back(Get<int8_t>(p));
        break;
      case sensor_msgs::PointField::UINT8:
        out.push_back(Get<uint8_t>(p));
        break;
      case sensor_msgs::PointField::INT16:
        out.push_back(Get<int16_t>(p));
        break;
      case sensor_msgs::PointField::UINT16:
        out.push_back(Get<uint16_t>(p));
        break;
      case sensor_msgs::PointField::INT32:
        out.push_back(Get<int32_t>(p));
        break;
      case sensor_msgs::PointField::UINT32:
        out.push_back(Get<uint32_t>(p));
        break;
      case sensor_msgs::PointField::FLOAT32:
        out.push_back(Get<float>(p));
        break;
      case sensor_msgs::PointField::FLOAT64:
        out.push_back(Get<double>(p));
        break;
      default:
        throw std::invalid_argument("cloud field '" + name + "' has unknown type " +
                                    std::to_string(f->datatype));
    }
  }
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
  out.height = 1;
  out.width = static_cast<uint32_t>(indices.size());
  out.row_step = out.point_step * out.width;
  out.is_dense = true;  // only finite points are selected by callers
  out.data.resize(static_cast<size_t>(out.row_step));
  for (size_t k = 0; k < indices.size(); ++k) {
    if (indices[k] >= static_cast<size_t>(msg.width) * msg.height)
      throw std::invalid_argument("point index beyond the cloud");
    std::memcpy(&out.data[k * out.point_step], PointAt(msg, indices[k]), out.point_step);
  }
  return out;
}

}  // namespace aar_registration
