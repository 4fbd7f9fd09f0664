#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "aar_ros_common/point_cloud.h"

namespace aar_ros_common {
namespace {

// A 2 x 3 organized cloud: x = index, y = 2 index, z = 3 index, label (uint16) = 10 index; the
// point at index 4 is NaN.
sensor_msgs::PointCloud2 MakeCloud() {
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = "camera";
  sensor_msgs::PointCloud2Modifier modifier(msg);
  modifier.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "label", 1, sensor_msgs::PointField::UINT16);
  msg.height = 2;
  msg.width = 3;
  msg.row_step = msg.width * msg.point_step;
  msg.data.resize(msg.row_step * msg.height);
  // Written byte-wise: in a 14-byte point the floats are not aligned (that is the point of this
  // cloud), and sensor_msgs' iterators would store through misaligned pointers.
  for (int i = 0; i < 6; ++i) {
    const float xyz[3] = {i == 4 ? NAN : static_cast<float>(i), 2.0f * i, 3.0f * i};
    const uint16_t label = static_cast<uint16_t>(10 * i);
    uint8_t* point = msg.data.data() + i * msg.point_step;
    std::memcpy(point, xyz, sizeof(xyz));
    std::memcpy(point + 12, &label, sizeof(label));
  }
  return msg;
}

TEST(PointCloud, ReadsFinitePointsWithTheirIndices) {
  const CloudPoints c = FromCloud(MakeCloud());
  ASSERT_EQ(c.points.size(), 5u);
  EXPECT_EQ(c.indices, (std::vector<uint32_t>{0, 1, 2, 3, 5}));
  EXPECT_TRUE(c.points[4].isApprox(Eigen::Vector3d(5, 10, 15)));
  EXPECT_EQ(ReadField(MakeCloud(), "label", c.indices), (std::vector<double>{0, 10, 20, 30, 50}));
  EXPECT_TRUE(HasField(MakeCloud(), "label"));
  EXPECT_FALSE(HasField(MakeCloud(), "rgb"));
}

TEST(PointCloud, ReadsRowsWithPadding) {
  const sensor_msgs::PointCloud2 plain = MakeCloud();
  sensor_msgs::PointCloud2 padded = plain;
  padded.row_step = plain.row_step + 8;
  padded.data.assign(padded.row_step * padded.height, 0xff);
  for (uint32_t r = 0; r < plain.height; ++r) {
    std::copy(plain.data.begin() + r * plain.row_step,
              plain.data.begin() + (r + 1) * plain.row_step,
              padded.data.begin() + r * padded.row_step);
  }
  const CloudPoints c = FromCloud(padded);
  EXPECT_EQ(c.indices, (std::vector<uint32_t>{0, 1, 2, 3, 5}));
  EXPECT_TRUE(c.points[3].isApprox(Eigen::Vector3d(3, 6, 9)));
  EXPECT_EQ(ReadField(padded, "label", {5}), (std::vector<double>{50}));
  const sensor_msgs::PointCloud2 selected = SelectPoints(padded, {5, 0});
  EXPECT_EQ(selected.width, 2u);
  EXPECT_EQ(selected.height, 1u);
  EXPECT_EQ(ReadField(selected, "label", {0, 1}), (std::vector<double>{50, 0}));
}

// 13-byte points (x, y, z float32 and a uint8 class, packed): every point after the first has
// its floats off their 4-byte alignment, which sensor_msgs' iterators read with undefined
// behaviour (the point_cloud fuzz target found it; UBSan reports it).
TEST(PointCloud, ReadsPackedPointsWhateverTheirAlignment) {
  sensor_msgs::PointCloud2 msg;
  msg.fields.resize(4);
  const char* names[] = {"x", "y", "z", "class"};
  for (uint32_t k = 0; k < 4; ++k) {
    msg.fields[k].name = names[k];
    msg.fields[k].offset = 4 * k;
    msg.fields[k].datatype =
        k < 3 ? sensor_msgs::PointField::FLOAT32 : sensor_msgs::PointField::UINT8;
    msg.fields[k].count = 1;
  }
  msg.point_step = 13;
  msg.width = 3;
  msg.height = 1;
  msg.row_step = 39;
  msg.data.resize(39);
  for (uint32_t i = 0; i < 3; ++i) {
    const float xyz[3] = {1.0f + i, 2.0f * i, 40.0f};
    std::memcpy(&msg.data[13 * i], xyz, sizeof(xyz));
    msg.data[13 * i + 12] = static_cast<uint8_t>(i + 1);
  }
  const CloudPoints c = FromCloud(msg);
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_TRUE(c.points[2].isApprox(Eigen::Vector3d(3, 4, 40)));
  EXPECT_EQ(ReadField(msg, "class", c.indices), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(ReadField(msg, "y", {1}), (std::vector<double>{2}));
  const sensor_msgs::PointCloud2 selected = SelectPoints(msg, {2, 1});
  EXPECT_TRUE(FromCloud(selected).points[0].isApprox(Eigen::Vector3d(3, 4, 40)));
}

TEST(PointCloud, SelectKeepsEveryFieldAndTheHeader) {
  const sensor_msgs::PointCloud2 selected = SelectPoints(MakeCloud(), {3, 1});
  EXPECT_EQ(selected.header.frame_id, "camera");
  EXPECT_EQ(selected.fields.size(), 4u);
  EXPECT_EQ(selected.row_step, 2 * selected.point_step);
  const CloudPoints c = FromCloud(selected);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_TRUE(c.points[0].isApprox(Eigen::Vector3d(3, 6, 9)));
  EXPECT_EQ(SelectPoints(MakeCloud(), {}).width, 0u);
}

TEST(PointCloud, BadCloudsAreNamed) {
  auto expect_error = [](const sensor_msgs::PointCloud2& msg, const std::string& part) {
    try {
      FromCloud(msg);
      ADD_FAILURE() << "no error, expected one containing '" << part << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  sensor_msgs::PointCloud2 msg = MakeCloud();
  msg.data.pop_back();
  expect_error(msg, "malformed");
  msg = MakeCloud();
  msg.is_bigendian = true;
  expect_error(msg, "big-endian");
  msg = MakeCloud();
  msg.fields[2].name = "w";
  expect_error(msg, "no float32 field 'z'");
  msg = MakeCloud();
  msg.fields[3].offset = msg.point_step - 1;
  expect_error(msg, "'label' exceeds point_step");
  msg = MakeCloud();
  msg.fields[3].datatype = 42;
  expect_error(msg, "unknown type 42");
  EXPECT_THROW(ReadField(MakeCloud(), "rgb", {0}), std::invalid_argument);
  EXPECT_THROW(ReadField(MakeCloud(), "label", {6}), std::invalid_argument);
  EXPECT_THROW(SelectPoints(MakeCloud(), {6}), std::invalid_argument);
  sensor_msgs::PointCloud2 empty = MakeCloud();
  empty.width = 0;
  empty.row_step = 0;
  empty.data.clear();
  EXPECT_TRUE(FromCloud(empty).points.empty());
}

}  // namespace
}  // namespace aar_ros_common
