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
  expect([&] { ToStereoGeometry(zero, r); },
         "left camera info (left) has no valid projection matrix P");
  sensor_msgs::CameraInfo no_baseline = r;
  no_baseline.P[3] = 0.0;
  expect([&] { ToStereoGeometry(l, no_baseline); }, "right camera info (right) P has no baseline");
  sensor_msgs::CameraInfo wrong_side = r;
  wrong_side.P[3] = 100.0;
  expect([&] { ToStereoGeometry(l, wrong_side); }, "must be negative");
  sensor_msgs::CameraInfo smaller = r;
  smaller.width = 640;
  expect([&] { ToStereoGeometry(l, smaller); }, "camera infos differ in size");
  // Found by the stereo_input fuzz target (issue 31): image_geometry asserted (aborted).
  sensor_msgs::CameraInfo binned = r;
  binned.binning_x = 2;
  expect([&] { ToStereoGeometry(l, binned); }, "differ in binning or in their region of interest");
  sensor_msgs::CameraInfo cropped = r;
  cropped.roi.y_offset = 10;
  expect([&] { ToStereoGeometry(l, cropped); }, "differ in binning or in their region of interest");
  sensor_msgs::CameraInfo nan = r;
  nan.P[2] = std::nan("");
  expect([&] { ToStereoGeometry(l, nan); }, "right camera info (right) P is not finite");

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

// Each bad camera info named with its problem and its topic (issue 15's bad input).
TEST(Conversions, BadCameraInfosNameTheTopic) {
  const auto [l, r] = Infos();
  auto expect = [](const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
                   const std::vector<std::string>& texts) {
    try {
      ToStereoGeometry(left, right, "/stereo/left/camera_info", "/stereo/right/camera_info");
      ADD_FAILURE() << "accepted: " << texts.front();
    } catch (const std::invalid_argument& e) {
      for (const auto& text : texts)
        EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  sensor_msgs::CameraInfo short_d = r;  // plumb_bob takes 5
  short_d.D = {-0.2, 0.1, 0.0};
  expect(l, short_d,
         {"right camera info (/stereo/right/camera_info) has 3 distortion coefficients D",
          "model plumb_bob takes 5"});
  sensor_msgs::CameraInfo rational = l;  // rational_polynomial takes 8
  rational.distortion_model = "rational_polynomial";
  expect(rational, r, {"left camera info (/stereo/left/camera_info) has 5", "takes 8"});
  sensor_msgs::CameraInfo unknown = l;
  unknown.distortion_model = "fisheye_42";
  expect(unknown, r, {"/stereo/left/camera_info", "distortion model 'fisheye_42'"});
  sensor_msgs::CameraInfo zero_f = l;
  zero_f.P[0] = 0.0;
  expect(zero_f, r, {"left camera info (/stereo/left/camera_info)", "zero focal length"});
  sensor_msgs::CameraInfo small = r;
  small.height = 480;
  expect(l, small,
         {"camera infos differ in size", "left (/stereo/left/camera_info) 1280x960",
          "right (/stereo/right/camera_info) 1280x480"});
  sensor_msgs::CameraInfo no_tx = r;
  no_tx.P[3] = 0.0;
  expect(l, no_tx, {"right camera info (/stereo/right/camera_info) P has no baseline"});
  // An empty D is no distortion, whatever the model (uncalibrated drivers send that).
  sensor_msgs::CameraInfo empty_d = l;
  empty_d.D.clear();
  empty_d.distortion_model = "";
  EXPECT_NO_THROW(ToStereoGeometry(empty_d, r));
}

// A raw camera's info (as aar_sim raw_images and camera_calibration give it: K, D, R of the raw
// camera, P the rectified projection): the geometry is P's, as image_geometry reads it, and the
// distortion is described for the warning.
TEST(Conversions, RawCameraInfosGiveTheRectifiedGeometry) {
  auto [l, r] = Infos();
  const double f = l.P[0];
  for (auto* info : {&l, &r}) {
    info->D = {-0.26, 0.09, 0.0006, -0.0004, -0.012};
    info->K = {f * 1.02, 0, 641.0, 0, f * 1.02, 478.0, 0, 0, 1};
    info->R = {0.99999, -0.0017, 0.0052, 0.0017, 0.99999, 0.0026, -0.0052, -0.0026, 0.99998};
  }
  r.header.frame_id = "stereo_right_optical";  // frames differ: not an image_geometry abort
  const StereoGeometry g = ToStereoGeometry(l, r);
  EXPECT_EQ(g.fx, f);
  EXPECT_EQ(g.cx_left, 639.5);
  EXPECT_EQ(g.cy, 479.5);
  EXPECT_NEAR(g.baseline(), 0.5, 1e-12);
  EXPECT_EQ(DescribeDistortion(l), "plumb_bob D = [-0.26, 0.09, 0.0006, -0.0004, -0.012]");
  const auto [l0, r0] = Infos();
  EXPECT_EQ(DescribeDistortion(l0), "");
  EXPECT_EQ(DistortionLength("equidistant"), 4);
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
