// bench_raw: what raw cameras cost per image (1280x960, config/sim.yaml's left lens): the
// simulator's RawCamera::Distort, and the rectification image_proc's rectify nodelet does for
// each image (cv::remap with the CV_16SC2 maps of cv::initUndistortRectifyMap, bilinear).
//   bench_raw [REPEATS]   (default 200; prints median and p95 [ms])
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "aar_sim/raw_camera.h"

namespace {

void Time(const char* what, int repeats, const std::function<void()>& f) {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    const auto a = std::chrono::steady_clock::now();
    f();
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count());
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%s: median %.2f ms, p95 %.2f ms (%d images)\n", what, ms[ms.size() / 2],
              ms[std::min(ms.size() - 1, ms.size() * 95 / 100)], repeats);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 200;
  if (repeats < 1) {
    std::fprintf(stderr, "usage: bench_raw [REPEATS >= 1]\n");
    return 2;
  }
  const auto k = aar_sim::CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0);
  const auto t0 = std::chrono::steady_clock::now();
  aar_sim::RawCamera camera(k, aar_sim::DefaultRawCameraOptions().left);
  std::printf(
      "RawCamera maps (once): %.0f ms\n",
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  camera.SetViewMargin(camera.margin_x(), camera.margin_y());
  aar_sim::Image<uint8_t> view;
  view.width = k.width + 2 * camera.margin_x();
  view.height = k.height + 2 * camera.margin_y();
  view.data.resize(static_cast<size_t>(view.width) * view.height);
  for (size_t i = 0; i < view.data.size(); ++i) view.data[i] = static_cast<uint8_t>(i * 7919 % 251);
  aar_sim::Image<uint8_t> raw;
  Time("sim: RawCamera::Distort", repeats, [&] { raw = camera.Distort(view); });

  const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = camera.R_rect_raw()(i, j);
  const cv::Mat D(1, 5, CV_64F, const_cast<double*>(camera.D().data()));
  cv::Mat m1, m2, rect;
  cv::initUndistortRectifyMap(K, D, R, K, cv::Size(k.width, k.height), CV_16SC2, m1, m2);
  const cv::Mat raw_cv(raw.height, raw.width, CV_8UC1, raw.data.data());
  Time("image_proc rectify: cv::remap", repeats,
       [&] { cv::remap(raw_cv, rect, m1, m2, cv::INTER_LINEAR); });
  return 0;
}
