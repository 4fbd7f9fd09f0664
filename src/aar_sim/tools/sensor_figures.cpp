// sensor_figures: the pictures of docs/realism/sensor.md, as PNGs in OUT_DIR: motion blur
// (sharp | blurred), noise at a dark and a bright sky (ideal | sensor), auto-exposure of a dark
// scene (fixed | auto). Crops of the left view at 1280x960, enlarged by whole pixels. Prints the
// largest image motion of the receiver within a 2 ms exposure along the path (what motion blur
// smears at config/realism/sensor.yaml's exposure).
//   sensor_figures FLIGHT_PATH OUT_DIR
#include <iostream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <aar_description/boom_model.h>
#include <ros/package.h>

#include "aar_sim/world.h"

namespace {

cv::Mat Crop(const aar_sim::Image<uint8_t>& image, const cv::Rect& box, int zoom) {
  const cv::Mat whole(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()));
  cv::Mat out;
  cv::resize(whole(box), out, cv::Size(), zoom, zoom, cv::INTER_NEAREST);
  return out;
}

// Tiles side by side with a white gap.
cv::Mat Row(const std::vector<cv::Mat>& tiles) {
  std::vector<cv::Mat> parts;
  for (size_t i = 0; i < tiles.size(); ++i) {
    if (i > 0) parts.push_back(cv::Mat(tiles[i].rows, 6, CV_8UC1, cv::Scalar(255)));
    parts.push_back(tiles[i]);
  }
  cv::Mat out;
  cv::hconcat(parts, out);
  return out;
}

// The receiver's box in the left view, grown by `margin` [px].
cv::Rect ReceiverBox(const aar_sim::StereoFrame& frame, int margin) {
  const auto& label = frame.left.label;
  int u0 = label.width, v0 = label.height, u1 = -1, v1 = -1;
  for (int v = 0; v < label.height; ++v)
    for (int u = 0; u < label.width; ++u)
      if (label.at(u, v) == static_cast<uint8_t>(aar_sim::Label::kReceiver))
        u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
  if (u1 < 0) throw std::runtime_error("the receiver is not in view");
  const cv::Rect box(u0 - margin, v0 - margin, u1 - u0 + 1 + 2 * margin, v1 - v0 + 1 + 2 * margin);
  return box & cv::Rect(0, 0, label.width, label.height);
}

// The largest image motion of the receiver's nose, tail and wing tips (about 7 m and 8 m from
// its origin) within a 2 ms exposure, every 0.1 s along the path.
void PrintLargestImageMotion(const aar_sim::FlightPath& path, const aar_sim::StereoRig& rig) {
  double largest = 0.0, at = 0.0;
  for (double t = path.start_time(); t + 0.002 <= path.end_time(); t += 0.1) {
    const auto a = path.At(t), b = path.At(t + 0.002);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(7, 0, 0), Eigen::Vector3d(-7, 0, 0),
                                     Eigen::Vector3d(0, 8, 0), Eigen::Vector3d(0, -8, 0)}) {
      const Eigen::Isometry3d T_optical_tanker = rig.T_tanker_left_optical.inverse();
      const double d = (rig.intrinsics.Project(T_optical_tanker * (b.T_tanker_receiver() * p)) -
                        rig.intrinsics.Project(T_optical_tanker * (a.T_tanker_receiver() * p)))
                           .norm();
      if (d > largest) largest = d, at = t;
    }
  }
  std::cout << "largest image motion of the receiver in 2 ms: " << largest << " px (t = " << at
            << " s)\n";
}

// Motion blur: 40 s into the approach (about 45 m), the receiver 0.3 m to the side and the boom
// 0.5 deg lower during the exposure (e.g. 15 m/s for 20 ms: exaggerated to be seen).
void WriteMotionBlurFigure(const aar_sim::WorldOptions& ideal, const aar_sim::FlightPath& path,
                           const aar_sim::BoomPose& boom, const std::string& out) {
  aar_sim::WorldOptions o = ideal;
  o.sensor.motion_blur = true;
  aar_sim::World world(o);
  const auto row = path.At(40.0);
  aar_sim::SceneState end{row, boom};
  end.row.position_m.y() += 0.3;
  end.boom.pitch += 0.5 * M_PI / 180.0;
  const auto sharp = world.Render(row, boom, 0, true, false);
  const auto blurred = world.Render(row, boom, 0, true, false, &end);
  const cv::Rect box = ReceiverBox(sharp, 12);
  cv::imwrite(out + "/sensor_motion_blur.png",
              Row({Crop(sharp.left.image, box, 1), Crop(blurred.left.image, box, 1)}));
}

// Noise: the sky at 40 and at 220 grey levels, a patch at the receiver's edge, without and with
// config/realism/sensor.yaml's noise (2 grey levels read noise, 10000 e- full well).
void WriteNoiseFigure(const aar_sim::WorldOptions& ideal, const aar_sim::FlightPath& path,
                      const aar_sim::BoomPose& boom, const std::string& out) {
  std::vector<cv::Mat> rows;
  for (const double sky : {40.0, 220.0}) {
    aar_sim::WorldOptions o = ideal;
    o.renderer.sky_level = sky;
    aar_sim::World clean(o);
    o.sensor.noise_stddev = 2.0;
    o.sensor.full_well = 10000.0;
    aar_sim::World noisy(o);
    const auto row = path.At(40.0);
    const auto a = clean.Render(row, boom, 0, true, false);
    const auto b = noisy.Render(row, boom, 0, true, false);
    const cv::Rect whole = ReceiverBox(a, 0);
    const cv::Rect box(whole.x - 30, whole.y + whole.height / 2 - 30, 60, 60);
    rows.push_back(Row({Crop(a.left.image, box, 4), Crop(b.left.image, box, 4)}));
  }
  cv::Mat figure;
  cv::vconcat(
      std::vector<cv::Mat>{rows[0], cv::Mat(6, rows[0].cols, CV_8UC1, cv::Scalar(255)), rows[1]},
      figure);
  cv::imwrite(out + "/sensor_noise.png", figure);
}

// Auto-exposure: a dark scene (sky at 50 grey levels), fixed exposure and auto-exposure.
void WriteAutoExposureFigure(const aar_sim::WorldOptions& ideal, const aar_sim::FlightPath& path,
                             const aar_sim::BoomPose& boom, const std::string& out) {
  aar_sim::WorldOptions o = ideal;
  o.renderer.sky_level = 50.0;
  aar_sim::World fixed(o);
  o.sensor.auto_exposure = true;
  aar_sim::World automatic(o);
  const auto row = path.At(30.0);
  const auto a = fixed.Render(row, boom, 0, true, false);
  const auto b = automatic.Render(row, boom, 0, true, false);
  const cv::Rect box = ReceiverBox(a, 40);
  cv::imwrite(out + "/sensor_auto_exposure.png",
              Row({Crop(a.left.image, box, 1), Crop(b.left.image, box, 1)}));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: sensor_figures FLIGHT_PATH OUT_DIR\n";
    return 2;
  }
  try {
    const std::string out = argv[2];
    const aar_sim::WorldOptions ideal =
        aar_sim::DefaultWorldOptions(ros::package::getPath("aar_description") + "/models");
    const auto path = aar_sim::FlightPath::Load(argv[1]);
    const aar_sim::BoomPose boom = aar_description::DefaultBoomPose();
    PrintLargestImageMotion(path, ideal.rig);
    WriteMotionBlurFigure(ideal, path, boom, out);
    WriteNoiseFigure(ideal, path, boom, out);
    WriteAutoExposureFigure(ideal, path, boom, out);
  } catch (const std::exception& e) {
    std::cerr << "sensor_figures: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
