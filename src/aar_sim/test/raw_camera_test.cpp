#include "aar_sim/raw_camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace aar_sim {
namespace {

const CameraIntrinsics kRect = CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0);

cv::Mat ToCv(const RawCamera& c, cv::Matx33d* K, cv::Matx33d* R) {
  const CameraIntrinsics& k = c.K();
  *K = cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) (*R)(i, j) = c.R_rect_raw()(i, j);
  return cv::Mat(1, 5, CV_64F, const_cast<double*>(c.D().data())).clone();
}

// image_proc rectifies with cv::initUndistortRectifyMap(K, D, R, P): for each rectified pixel,
// the raw pixel it takes. The raw camera must send each of those raw pixels back to it.
TEST(RawCamera, InverseOfImageProcsRectification) {
  for (const LensOptions& lens :
       {DefaultRawCameraOptions().left, DefaultRawCameraOptions().right}) {
    const RawCamera camera(kRect, lens);
    cv::Matx33d K, R;
    const cv::Mat D = ToCv(camera, &K, &R);
    cv::Mat map_x, map_y;
    cv::initUndistortRectifyMap(K, D, R, K, cv::Size(kRect.width, kRect.height), CV_32FC1, map_x,
                                map_y);
    double worst = 0.0;
    for (int v = 0; v < kRect.height; v += 37) {
      for (int u = 0; u < kRect.width; u += 41) {
        const Eigen::Vector2d rect =
            camera.RectifiedPixel(map_x.at<float>(v, u), map_y.at<float>(v, u));
        worst = std::max(worst, (rect - Eigen::Vector2d(u, v)).norm());
      }
    }
    EXPECT_LT(worst, 1e-3);  // [px] image_proc-style float maps; measured 8.5e-5
    // Barrel: the raw corner looks beyond the rectified view; about 10 % at the corners.
    const Eigen::Vector2d corner = camera.RectifiedPixel(0.0, 0.0);
    EXPECT_LT(corner.x(), -80.0);                // [px] measured -115 (left), -89 (right)
    EXPECT_LT(corner.y(), -50.0);                // [px] measured -88, -63
    EXPECT_GT(camera.outside_fraction(), 0.10);  // measured 0.153 (left), 0.143 (right)
    EXPECT_LT(camera.outside_fraction(), 0.20);
    // The margins cover every raw pixel's rectified position.
    EXPECT_GE(camera.margin_x(), -corner.x());
    EXPECT_GE(camera.margin_y(), -corner.y());
    EXPECT_LT(camera.margin_x(), 200);
  }
}

// Distort, then rectify as image_proc does: the rectified view comes back (blurred only by two
// linear interpolations) wherever the raw camera saw it.
TEST(RawCamera, DistortThenRectifyGivesTheViewBack) {
  Image<uint8_t> rect;
  rect.width = kRect.width;
  rect.height = kRect.height;
  rect.data.resize(static_cast<size_t>(rect.width) * rect.height);
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u)
      rect.at(u, v) = static_cast<uint8_t>(128 + 100 * std::sin(u / 23.0) * std::cos(v / 17.0));
  const RawCamera camera(kRect, DefaultRawCameraOptions().left);
  const Image<uint8_t> raw = camera.Distort(rect);
  ASSERT_EQ(raw.width, rect.width);
  ASSERT_EQ(raw.height, rect.height);
  cv::Matx33d K, R;
  const cv::Mat D = ToCv(camera, &K, &R);
  cv::Mat m1, m2, back;
  cv::initUndistortRectifyMap(K, D, R, K, cv::Size(kRect.width, kRect.height), CV_16SC2, m1, m2);
  const cv::Mat raw_cv(raw.height, raw.width, CV_8UC1, const_cast<uint8_t*>(raw.data.data()));
  cv::remap(raw_cv, back, m1, m2, cv::INTER_LINEAR);
  double sum = 0.0, moved = 0.0;
  int n = 0;
  for (int v = 40; v < kRect.height - 40; v += 3) {
    for (int u = 40; u < kRect.width - 40; u += 3, ++n) {
      sum += std::abs(back.at<uint8_t>(v, u) - rect.at(u, v));
      moved += std::abs(raw.at(u, v) - rect.at(u, v));
    }
  }
  EXPECT_LT(sum / n, 0.2);     // [grey levels] measured 0.061
  EXPECT_GT(moved / n, 25.0);  // the raw image really differs (measured 35)
}

TEST(RawCamera, NoDistortionNoRotationIsTheIdentity) {
  const RawCamera camera(kRect, LensOptions{});
  EXPECT_NEAR((camera.RectifiedPixel(3.0, 900.0) - Eigen::Vector2d(3.0, 900.0)).norm(), 0.0, 1e-6);
  Image<uint8_t> rect;
  rect.width = kRect.width;
  rect.height = kRect.height;
  rect.data.resize(static_cast<size_t>(rect.width) * rect.height);
  for (size_t i = 0; i < rect.data.size(); ++i) rect.data[i] = static_cast<uint8_t>(i * 7 % 251);
  EXPECT_EQ(camera.Distort(rect).data, rect.data);
  EXPECT_EQ(camera.outside_fraction(), 0.0);
}

TEST(RawCamera, BadLensesAreRefusedNamed) {
  LensOptions folding;
  folding.distortion = {-3.0, 0.0, 0.0, 0.0, 0.0};
  try {
    RawCamera camera(kRect, folding);
    ADD_FAILURE() << "a folding lens was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("folds"), std::string::npos) << e.what();
  }
  LensOptions nan;
  nan.distortion[1] = std::nan("");
  EXPECT_THROW(RawCamera(kRect, nan), std::invalid_argument);
  Image<uint8_t> small;
  small.width = 4;
  small.height = 4;
  small.data.resize(16);
  EXPECT_THROW(RawCamera(kRect, LensOptions{}).Distort(small), std::invalid_argument);
}

}  // namespace
}  // namespace aar_sim
