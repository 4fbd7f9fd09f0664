#include "aar_stereo/ros/conversions.h"

#include <gtest/gtest.h>

#include <image_geometry/stereo_camera_model.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace aar_stereo {
namespace {

// The camera infos aar_sim publishes (1280x960, 60 deg, 0.5 m).
std::pair<sensor_msgs::CameraInfo, sensor_msgs::CameraInfo> Infos() {
  sensor_msgs::CameraInfo l;
  l.width = 1280;
  l.height = 960;
  const double f = 640.0 / std::tan(M_PI / 6.0);
  l.K = {f, 0, 639.5, 0, f, 479.5, 0, 0, 1};
  l.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  l.P = {f, 0, 639.5, 0, 0, f, 479.5, 0, 0, 0, 1, 0};
  l.D.assign(5, 0.0);
  l.distortion_model = "plumb_bob";
  l.header.frame_id = "stereo_left_optical";
  sensor_msgs::CameraInfo r = l;
  r.P[3] = -f * 0.5;
  return {l, r};
}

TEST(Conversions, QEqualsImageGeometrysStereoModel) {
  const auto [l, r] = Infos();
  image_geometry::StereoCameraModel model;
  sensor_msgs::CameraInfo r_same = r;  // image_geometry asserts equal frames
  r_same.header.frame_id = l.header.frame_id;
  model.fromCameraInfo(l, r_same);
  const StereoGeometry g = ToStereoGeometry(l, r);
  EXPECT_NEAR(g.baseline(), model.baseline(), 1e-12);
  for (const auto& [u, v, d] : std::vector<std::tuple<double, double, float>>{
           {100, 200, 5.0f}, {640, 480, 0.75f}, {1200, 30, 40.5f}}) {
    cv::Point3d expected;
    model.projectDisparityTo3d(cv::Point2d(u, v), d, expected);
    const cv::Vec4d h = g.Q() * cv::Vec4d(u, v, d, 1.0);
    EXPECT_NEAR(h[0] / h[3], expected.x, 1e-9);
    EXPECT_NEAR(h[1] / h[3], expected.y, 1e-9);
    EXPECT_NEAR(h[2] / h[3], expected.z, 1e-9);
  }
}

TEST(Conversions, BadCameraInfosAndImagesNameTheProblem) {
  auto [l, r] = Infos();
  auto expect = [](auto&& f, const std::string& text) {
    try {
      f();
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  sensor_msgs::CameraInfo zero = l;
  zero.P.fill(0.0);
  expect([&] { ToStereoGeometry(zero, r); }, "left camera info has no valid projection matrix P");
  sensor_msgs::CameraInfo no_baseline = r;
  no_baseline.P[3] = 0.0;
  expect([&] { ToStereoGeometry(l, no_baseline); }, "must be negative");
  sensor_msgs::CameraInfo smaller = r;
  smaller.width = 640;
  expect([&] { ToStereoGeometry(l, smaller); }, "camera infos differ in size");
  sensor_msgs::CameraInfo nan = r;
  nan.P[2] = std::nan("");
  expect([&] { ToStereoGeometry(l, nan); }, "right camera info P is not finite");

  sensor_msgs::Image image;
  image.encoding = sensor_msgs::image_encodings::RGB8;
  image.width = 4;
  image.height = 2;
  image.step = 12;
  image.data.resize(24);
  expect([&] { ToMono8(image, "left"); }, "left image has encoding 'rgb8'");
  image.encoding = sensor_msgs::image_encodings::MONO8;
  image.step = 4;
  image.data.resize(5);
  expect([&] { ToMono8(image, "right"); }, "right image is malformed");
}

TEST(Conversions, PointCloudFieldsAndShape) {
  CloudPoints cloud;
  cloud.xyz = {{1, 2, 3}, {4, 5, 6}};
  cloud.intensity = {10, 20};
  cloud.width = 2;
  std_msgs::Header header;
  header.frame_id = "stereo_left_optical";
  const auto msg = ToPointCloud2Msg(cloud, header);
  EXPECT_EQ(msg->width, 2u);
  EXPECT_EQ(msg->height, 1u);
  EXPECT_EQ(msg->fields.size(), 4u);
  EXPECT_TRUE(msg->is_dense);
  sensor_msgs::PointCloud2ConstIterator<float> z(*msg, "z"), in(*msg, "intensity");
  ++z;
  ++in;
  EXPECT_EQ(*z, 6.0f);
  EXPECT_EQ(*in, 20.0f);
}

// A frame without a valid disparity: the fields and no data (the stereo_input fuzz target found
// the iterators taking data.front() of the empty data, undefined behaviour UBSan reports).
TEST(Conversions, EmptyCloudHasFieldsAndNoPoints) {
  CloudPoints cloud;
  cloud.width = 0;
  const auto msg = ToPointCloud2Msg(cloud, std_msgs::Header());
  EXPECT_EQ(msg->width, 0u);
  EXPECT_EQ(msg->height, 1u);
  EXPECT_EQ(msg->fields.size(), 3u);
  EXPECT_EQ(msg->point_step, 16u);  // sensor_msgs pads "xyz" to 16 bytes
  EXPECT_TRUE(msg->data.empty());
}

}  // namespace
}  // namespace aar_stereo
