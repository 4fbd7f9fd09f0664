// Fuzz target point_cloud: a sensor_msgs/PointCloud2 deserialized from the bytes (as roscpp
// hands one to a subscriber), read as the occlusion and registration nodes read their clouds:
// aar_ros_common::FromCloud, ReadField of every field, SelectPoints, and
// aar_registration::ToReferencePoints. Each may refuse a cloud with std::invalid_argument.
#include <cstdint>
#include <stdexcept>

#include <aar_registration/ros/conversions.h>
#include <aar_ros_common/point_cloud.h>
#include <sensor_msgs/PointCloud2.h>

#include "fuzz_support.h"

namespace {

using aar_ros_common::CloudPoints;

void CheckSelection(const sensor_msgs::PointCloud2& msg, const CloudPoints& points) {
  const sensor_msgs::PointCloud2 selected = aar_ros_common::SelectPoints(msg, points.indices);
  FUZZ_CHECK(selected.width == points.indices.size() && selected.height == 1,
             "SelectPoints keeps one point per index");
  const CloudPoints again = aar_ros_common::FromCloud(selected);  // a selection reads back
  FUZZ_CHECK(again.points.size() == points.points.size(), "the selection reads back whole");
  for (size_t i = 0; i < again.points.size(); ++i) {
    FUZZ_CHECK(again.indices[i] == i, "the selection is dense");
    FUZZ_CHECK(again.points[i] == points.points[i], "the selection keeps the points");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ros::serialization::IStream stream(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
  sensor_msgs::PointCloud2 msg;
  if (!aar_fuzz::NextMessage<sensor_msgs::PointCloud2_>(stream, msg)) return 0;

  const size_t n = static_cast<size_t>(msg.width) * msg.height;
  CloudPoints points;
  bool readable = true;
  try {
    points = aar_ros_common::FromCloud(msg);
  } catch (const std::invalid_argument&) {
    readable = false;
  }
  if (readable) {
    FUZZ_CHECK(points.points.size() == points.indices.size(), "a point per index");
    for (size_t i = 0; i < points.points.size(); ++i) {
      FUZZ_CHECK(points.points[i].allFinite(), "FromCloud returns finite points");
      FUZZ_CHECK(points.indices[i] < n, "indices lie in the cloud");
      FUZZ_CHECK(i == 0 || points.indices[i] > points.indices[i - 1], "indices increase");
    }
    CheckSelection(msg, points);
  }

  // Every field at the finite points (or, for a cloud without x, y, z, at its first points).
  std::vector<uint32_t> indices = points.indices;
  if (!readable) {
    for (uint32_t i = 0; i < n && i < 64; ++i) indices.push_back(i);
  }
  for (const auto& field : msg.fields) {
    try {
      const std::vector<double> values = aar_ros_common::ReadField(msg, field.name, indices);
      FUZZ_CHECK(values.size() == indices.size(), "a value per index");
    } catch (const std::invalid_argument& e) {
      FUZZ_CHECK(!readable, "ReadField refuses field '" + field.name +
                                "' of a cloud FromCloud read: " + e.what());
    }
  }
  if (n < UINT32_MAX && !msg.fields.empty()) {
    bool refused = false;
    try {
      aar_ros_common::ReadField(msg, msg.fields[0].name, {static_cast<uint32_t>(n)});
    } catch (const std::invalid_argument&) {
      refused = true;
    }
    FUZZ_CHECK(refused, "an index beyond the cloud is refused");
  }

  try {
    const aar_registration::ReferencePoints reference = aar_registration::ToReferencePoints(msg);
    FUZZ_CHECK(reference.normals.empty() || reference.normals.size() == reference.points.size(),
               "a normal per reference point, or none");
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
