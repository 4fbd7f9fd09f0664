// bench_stereo: on simulated frames along the default approach (1280x960, boom shown),
//  1. receiver and boom points per frame after decimation, told apart by the simulator's labels;
//  2. per-frame latency of aar_stereo and of stereo_image_proc's processor (disparity + points2)
//     on the same pair with the same block-matching settings, side by side;
//  3. aar_stereo matching only a region of interest around the predicted receiver and boom
//     projection (here from truth, standing in for the last estimate), its speedup and the
//     receiver points it keeps.
//   bench_stereo [FRAMES] [REPEATS] [CSV]
// AAR_RECEIVER (a receiver description, e.g. aar_description/models/rq4.yaml) and
// AAR_FLIGHT_PATH (its approach) put another receiver on another path. AAR_BACKGROUND (sea or
// terrain, with config/realism/background.yaml's 40 % cloud layer) puts a background behind the
// receiver: "other" then counts the background points that survive the stereo stage.
// AAR_SUN=1 turns the sun on (config/realism/sun.yaml: shadows, glare) and AAR_PROPELLERS (blades
// or disc; blades smeared over a 2 ms exposure) draws the receiver's propellers: "prop" counts
// the points on pixels their blades cover at least half the exposure (issue 16). AAR_DISP12=N
// runs block matching with its left-right check at N px.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <aar_description/boom_model.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/robot_model.h>
#include <aar_stereo/stereo.h>
#include <aar_testing/sim_stereo.h>
#include <aar_testing/timing.h>
#include <image_geometry/stereo_camera_model.h>
#include <sensor_msgs/PointCloud2.h>
#include <stereo_image_proc/processor.h>
#include <stereo_msgs/DisparityImage.h>

namespace {

using Clock = std::chrono::steady_clock;

sensor_msgs::CameraInfo Info(const aar_sim::CameraIntrinsics& k, double Tx) {
  sensor_msgs::CameraInfo info;
  info.header.frame_id = "stereo_left_optical";
  info.width = k.width;
  info.height = k.height;
  info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {k.fx, 0, k.cx, Tx, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  info.D.assign(5, 0.0);
  info.distortion_model = "plumb_bob";
  return info;
}

struct Counts {
  int receiver = 0, boom = 0, other = 0;
  int background = 0;  // of `other`: on ground or cloud pixels (AAR_BACKGROUND)
  int far = 0;         // farther than 100 m from the camera: not on the receiver or boom
  int propeller = 0;   // of `other`: on propeller pixels (AAR_PROPELLERS)
};

Counts Count(const aar_stereo::CloudPoints& cloud, const aar_sim::Image<uint8_t>& label) {
  Counts c;
  for (size_t i = 0; i < cloud.pixel.size(); ++i) {
    c.far += cloud.xyz[i].norm() > 100.0f;
    const uint8_t l = label.data[cloud.pixel[i]];
    c.background += l == static_cast<uint8_t>(aar_sim::Label::kGround) ||
                    l == static_cast<uint8_t>(aar_sim::Label::kCloud);
    c.propeller += l == static_cast<uint8_t>(aar_sim::Label::kPropeller);
    (l == static_cast<uint8_t>(aar_sim::Label::kReceiver) ? c.receiver
     : l == static_cast<uint8_t>(aar_sim::Label::kBoom)   ? c.boom
                                                          : c.other)++;
  }
  return c;
}

}  // namespace

// The sparse matcher (issue 28) on the receiver's box as the node predicts it (grown 2 m, 16 px),
// searched up to the nearest disparity of the box and, where it crosses, of the boom: its time,
// its receiver points and the share of its samples where it and block matching (the thesis's,
// speckle filter on) agree within 1/16 px, of those where either gives a disparity.
struct SparseRow {
  double ms = 0, agree = 0;
  int receiver = 0, stride = 0;
};
SparseRow Sparse(const cv::Mat& left, const cv::Mat& right, const aar_stereo::StereoGeometry& g,
                 const std::vector<Eigen::Vector3d>& receiver,
                 const std::vector<Eigen::Vector3d>& boom, const aar_stereo::StereoResult& dense,
                 const aar_sim::Image<uint8_t>& label, int repeats) {
  aar_stereo::StereoOptions o;
  o.matcher = aar_stereo::Matcher::kSparse;
  const aar_stereo::StereoProcessor sparse(o);
  const cv::Rect roi = aar_stereo::ProjectedRoi(receiver, g, 16);
  const std::vector<aar_stereo::DisparityZone> zones = {
      {roi, aar_stereo::MaxDisparity(receiver, g)},
      {aar_stereo::ProjectedRoi(boom, g, 16), aar_stereo::MaxDisparity(boom, g)}};
  const aar_stereo::StereoResult r = sparse.Process(left, right, g, roi, zones);
  SparseRow row;
  row.ms = aar_testing::MedianMs(repeats, [&] { sparse.Process(left, right, g, roi, zones); });
  row.receiver = Count(r.cloud, label).receiver;
  row.stride = r.samples.stride;
  int either = 0, agree = 0;
  const int s = r.samples.stride;
  for (int v = roi.y - roi.y % s; v < roi.y + roi.height; v += s)
    for (int u = roi.x - roi.x % s; u < roi.x + roi.width; u += s) {
      if (!roi.contains(cv::Point(u, v))) continue;
      const float a = r.disparity.at<float>(v, u), b = dense.disparity.at<float>(v, u);
      if (a < 0 && b < 0) continue;
      ++either;
      agree += a >= 0 && b >= 0 && std::abs(a - b) <= 1.0f / 16 + 1e-4f;
    }
  row.agree = either > 0 ? static_cast<double>(agree) / either : 1.0;
  return row;
}

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::stoi(argv[1]) : 12;
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 5;
  const std::string csv = argc > 3 ? argv[3] : "";
  try {
    aar_sim::WorldOptions w = aar_testing::SimStereo::DefaultWorld();
    // AAR_RIG_X, AAR_RIG_Y, AAR_RIG_Z [m] and AAR_RIG_PITCH [deg down] move the rig (defaults:
    // config/sim.yaml's, 1 m left of the boom plane), for trying other camera mounts.
    auto env = [](const char* name, double fallback) {
      return std::getenv(name) ? std::stod(std::getenv(name)) : fallback;
    };
    w.rig = aar_sim::MakeStereoRig(
        aar_sim::CameraIntrinsics::FromHorizontalFov(1280, 960, 60.0), 0.5,
        {env("AAR_RIG_X", -20.0), env("AAR_RIG_Y", 1.0), env("AAR_RIG_Z", -3.0)}, 180.0,
        env("AAR_RIG_PITCH", 25.0));
    if (const char* background = std::getenv("AAR_BACKGROUND"); background && *background) {
      w.renderer.scene.background = std::string(background) == "sea"
                                        ? aar_sim::Background::kSea
                                        : aar_sim::Background::kTerrain;
      w.renderer.scene.cloud_coverage = 0.4;
    }
    if (const char* sun = std::getenv("AAR_SUN"); sun && std::string(sun) == "1")
      w.renderer.sun.enabled = true;  // sun.yaml's values are SunOptions' defaults
    if (const char* props = std::getenv("AAR_PROPELLERS"); props && *props) {
      w.propellers = std::string(props) == "disc" ? aar_sim::PropellerMode::kDisc
                                                  : aar_sim::PropellerMode::kBlades;
      w.sensor.motion_blur = true;  // the blades' smear only: nothing is given an exposure end
      w.sensor.exposure_time = 0.002;
    }
    if (std::getenv("AAR_RECEIVER"))
      w.receiver = aar_description::LoadReceiverDescription(std::getenv("AAR_RECEIVER"));
    aar_stereo::StereoOptions options;  // thesis defaults: BM 9 / 48, every 8th point
    // AAR_DISP12 [px] turns block matching's left-right check on (disp12_max_diff).
    if (const char* d = std::getenv("AAR_DISP12"); d && *d) options.disp12_max_diff = std::stoi(d);
    aar_testing::SimStereo sim(w, options);
    aar_sim::World& world = sim.world();
    const auto path = aar_sim::FlightPath::Load(std::getenv("AAR_FLIGHT_PATH")
                                                    ? std::getenv("AAR_FLIGHT_PATH")
                                                    : aar_testing::DefaultApproachPath());
    const aar_sim::CameraIntrinsics& k = w.rig.intrinsics;
    const aar_stereo::StereoGeometry& g = sim.geometry();
    aar_stereo::StereoOptions all = options;
    all.decimation = aar_stereo::Decimation::kNone;
    const aar_stereo::StereoProcessor ours(options), ours_all(all);

    stereo_image_proc::StereoProcessor sip;
    sip.setStereoType(stereo_image_proc::StereoProcessor::BM);
    sip.setCorrelationWindowSize(options.block_size);
    sip.setDisparityRange(options.num_disparities);
    sip.setMinDisparity(options.min_disparity);
    sip.setPreFilterSize(options.prefilter_size);
    sip.setPreFilterCap(options.prefilter_cap);
    sip.setTextureThreshold(options.texture_threshold);
    sip.setUniquenessRatio(options.uniqueness_ratio);
    sip.setSpeckleSize(options.speckle_window_size);
    sip.setSpeckleRange(options.speckle_range);
    image_geometry::StereoCameraModel model;
    model.fromCameraInfo(Info(k, 0.0), Info(k, g.Tx));

    // Boom collision geometry (link frames) for the region of interest.
    std::ofstream out;
    if (!csv.empty()) {
      out.open(csv);
      out << "t,range_m,receiver_points,boom_points,other_points,aar_stereo_ms,stereo_image_proc_"
             "ms,roi_ms,"
             "roi_fraction,receiver_valid_full,receiver_valid_roi,sparse_ms,sparse_receiver_points,"
             "sparse_stride,sparse_agree_bm\n";
    }
    std::printf("%6s %8s %9s %6s %6s %6s %6s %6s %9s %9s %8s %8s %8s %10s %10s %10s %10s %6s %8s\n",
                "t[s]", "range[m]", "receiver", "boom", "other", "bg", "far", "prop", "aar[ms]",
                "sip[ms]", "roi[ms]", "speedup", "roi area", "rcv full", "rcv roi", "sparse[ms]",
                "rcv sparse", "stride", "=BM");
    for (int i = 0; i < frames; ++i) {
      const double t =
          path.start_time() + (path.end_time() - path.start_time()) * i / std::max(1, frames - 1);
      const aar_sim::FlightPathRow row = path.At(t);
      const aar_sim::StereoFrame f =
          world.Render(row, aar_description::DefaultBoomPose(), i, true, false);
      const cv::Mat left = sim.Left(f), right = sim.Right(f);

      const aar_stereo::StereoResult result = ours.Process(left, right, g);
      const Counts counts = Count(result.cloud, f.left.label);
      const double ours_ms = aar_testing::MedianMs(repeats, [&] { ours.Process(left, right, g); });
      const double sip_ms = aar_testing::MedianMs(repeats, [&] {
        stereo_msgs::DisparityImage disparity;
        sensor_msgs::PointCloud2 points;
        sip.processDisparity(left, right, model, disparity);
        sip.processPoints2(disparity, left, "mono8", model, points);
      });

      // Region of interest: receiver bounding-box corners and boom collision vertices.
      const Eigen::Isometry3d T_optical_tanker = w.rig.T_tanker_left_optical.inverse();
      std::vector<Eigen::Vector3d> predicted;
      const Eigen::AlignedBox3d box = world.receiver_mesh().Bounds();
      for (int c = 0; c < 8; ++c) {
        predicted.push_back(T_optical_tanker * f.T_tanker_receiver *
                            box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
      }
      const auto boom = aar_geometry::RobotMesh(world.boom_model(), f.T_tanker_links,
                                                aar_geometry::GeometryKind::kCollision);
      for (const auto& v : boom.vertices) predicted.push_back(T_optical_tanker * v);
      const cv::Rect roi = aar_stereo::ProjectedRoi(predicted, g, 16);
      const double roi_ms =
          aar_testing::MedianMs(repeats, [&] { ours.Process(left, right, g, roi); });
      const aar_stereo::StereoResult dense_all = ours_all.Process(left, right, g);
      const Counts full_all = Count(dense_all.cloud, f.left.label);
      std::vector<Eigen::Vector3d> receiver;
      for (const auto& c : aar_stereo::BoxCorners(box, T_optical_tanker * f.T_tanker_receiver, 2.0))
        receiver.push_back(c);
      std::vector<Eigen::Vector3d> boom_optical;
      for (const auto& v : boom.vertices) boom_optical.push_back(T_optical_tanker * v);
      const SparseRow sparse =
          Sparse(left, right, g, receiver, boom_optical, dense_all, f.left.label, repeats);
      const Counts roi_all = Count(ours_all.Process(left, right, g, roi).cloud, f.left.label);
      const double area = static_cast<double>(roi.area()) / (k.width * k.height);

      std::printf(
          "%6.1f %8.1f %9d %6d %6d %6d %6d %6d %9.1f %9.1f %8.1f %8.2f %7.1f%% %10d %10d %10.2f "
          "%10d %6d %7.1f%%\n",
          t, row.position_m.norm(), counts.receiver, counts.boom, counts.other, counts.background,
          counts.far, counts.propeller, ours_ms, sip_ms, roi_ms, ours_ms / roi_ms, 100.0 * area,
          full_all.receiver, roi_all.receiver, sparse.ms, sparse.receiver, sparse.stride,
          100.0 * sparse.agree);
      if (out) {
        out << t << ',' << row.position_m.norm() << ',' << counts.receiver << ',' << counts.boom
            << ',' << counts.other << ',' << ours_ms << ',' << sip_ms << ',' << roi_ms << ','
            << area << ',' << full_all.receiver << ',' << roi_all.receiver << ',' << sparse.ms
            << ',' << sparse.receiver << ',' << sparse.stride << ',' << sparse.agree << '\n';
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_stereo: %s\n", e.what());
    return 1;
  }
  return 0;
}
