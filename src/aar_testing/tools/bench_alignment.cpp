// The outline alignment (aar_alignment) on rendered frames of the shipped approach, by range:
// from starts off the truth by a fixed position and attitude error in seeded random directions,
// the error left after alignment, its time, lines and quality; with the boom masked out.
//   bench_alignment [ideal|realistic] [starts per range] [position error m] [attitude error deg]
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include <aar_alignment/aligner.h>
#include <aar_alignment/boom_parts.h>
#include <aar_description/boom_model.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/pose_error.h>
#include <aar_occlusion/boom.h>
#include <aar_sim/flight_path.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aar_testing/alignment_views.h"
#include "aar_testing/paths.h"
#include "aar_testing/sim_stereo.h"

int main(int argc, char** argv) {
  const std::string world = argc > 1 ? argv[1] : "ideal";
  const int starts = argc > 2 ? std::atoi(argv[2]) : 5;
  const double position_error = argc > 3 ? std::atof(argv[3]) : 2.0;
  const double attitude_error = aar_geometry::DegToRad(argc > 4 ? std::atof(argv[4]) : 3.0);
  if (world != "ideal" && world != "realistic") {
    std::fprintf(stderr, "bench_alignment: world must be ideal or realistic, not '%s'\n",
                 world.c_str());
    return 2;
  }
  aar_testing::SimStereo sim(world == "ideal" ? aar_testing::SimStereo::DefaultWorld()
                                              : aar_testing::RealisticWorld());
  const auto path = aar_sim::FlightPath::Load(aar_testing::DefaultApproachPath());
  const auto boom = aar_occlusion::LoadBoomParts(aar_testing::LoadBoomModel());
  aar_alignment::AlignmentOptions options;
  if (const char* model = std::getenv("AAR_ALIGN_MODEL"))
    options.line_model = aar_alignment::ParseLineModel(model);
  if (const char* radius = std::getenv("AAR_ALIGN_SEARCH"))
    options.search_radius_px = std::atof(radius);
  if (const char* scales = std::getenv("AAR_ALIGN_SCALES")) {  // e.g. "5,3,2,1"
    options.scales.clear();
    for (const char* c = scales; *c;) {
      options.scales.push_back(std::strtod(c, const_cast<char**>(&c)));
      if (*c == ',') ++c;
    }
  }
  const aar_alignment::OutlineAligner aligner(sim.world().receiver_mesh(), options);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  auto direction = [&]() {
    Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
    return d.normalized();
  };
  std::printf("world %s, %d starts per range, start error %.2f m and %.2f deg\n", world.c_str(),
              starts, position_error, aar_geometry::RadToDeg(attitude_error));
  std::printf("%6s %7s | %8s %8s %8s | %7s %7s %6s %5s | %s\n", "t [s]", "range", "|dx| mean",
              "|dx| max", "ang max", "quality", "inlier", "lines", "ms", "failures");
  std::vector<double> times = {0.5,  5.0,  10.0, 15.0, 20.0, 25.0,
                               30.0, 35.0, 40.0, 44.0, 48.0, 50.5};
  if (const char* only = std::getenv("AAR_ALIGN_T")) times = {std::atof(only)};
  for (const double t : times) {
    const aar_sim::FlightPathRow row = path.At(t);
    const aar_sim::StereoFrame f =
        sim.world().Render(row, aar_description::DefaultBoomPose(), static_cast<uint64_t>(t * 30));
    aar_alignment::AlignmentInput in;
    in.left = sim.Left(f);
    in.right = sim.Right(f);
    in.left_camera = aar_testing::LeftCamera(sim.rig());
    in.right_camera = aar_testing::RightCamera(sim.rig());
    in.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(boom, f.T_tanker_links);
    // The prediction's covariance as a tracker would give it: the start's error per axis.
    aar_alignment::Vector6d sigma;
    sigma << Eigen::Vector3d::Constant(std::max(0.05, position_error)),
        Eigen::Vector3d::Constant(std::max(0.005, attitude_error));
    in.prediction_covariance = sigma.cwiseAbs2().asDiagonal();
    if (const char* dump = std::getenv("AAR_ALIGN_DUMP")) {  // the outline at the truth, drawn
      cv::Mat colour;
      cv::cvtColor(in.left, colour, cv::COLOR_GRAY2BGR);
      for (const auto& c : aligner.model().Contour(in.left_camera, f.T_tanker_receiver, 200)) {
        const cv::Point a(cvRound(c.pixel.x()), cvRound(c.pixel.y()));
        cv::line(colour, a, a + cv::Point(cvRound(6 * c.normal.x()), cvRound(6 * c.normal.y())),
                 cv::Scalar(0, 0, 255));
        cv::circle(colour, a, 1, cv::Scalar(0, 255, 0), -1);
      }
      cv::imwrite(std::string(dump) + "_" + std::to_string(static_cast<int>(t)) + ".png", colour);
    }
    double sum = 0.0, worst = 0.0, angle = 0.0, quality = 0.0, inliers = 0.0, ms = 0.0;
    int lines = 0, failures = 0;
    for (int s = 0; s < starts; ++s) {
      Eigen::Isometry3d start = f.T_tanker_receiver;
      start.translation() += position_error * direction();
      start.linear() =
          Eigen::AngleAxisd(attitude_error, direction()).toRotationMatrix() * start.linear();
      in.T_tanker_receiver_predicted = start;
      const aar_alignment::AlignmentResult r = aligner.Align(in);
      if (!r.valid) {
        ++failures;
        std::printf("  t %.1f: %s\n", t, r.error.c_str());
        continue;
      }
      const auto e = aar_geometry::ComputePoseError(f.T_tanker_receiver, r.T_tanker_receiver);
      if (std::getenv("AAR_ALIGN_VERBOSE")) {
        const auto e0 = aar_geometry::ComputePoseError(f.T_tanker_receiver, start);
        std::printf(
            "  start x %6.2f %6.2f %6.2f rpy %5.1f %5.1f %5.1f -> x %6.2f %6.2f %6.2f rpy %5.1f "
            "%5.1f %5.1f q %.2f shift %.1f %.1f sd %.2f %.2f %.2f %.1f %.1f %.1f\n",
            e0.position_m.x(), e0.position_m.y(), e0.position_m.z(),
            aar_geometry::RadToDeg(e0.orientation_rad.roll),
            aar_geometry::RadToDeg(e0.orientation_rad.pitch),
            aar_geometry::RadToDeg(e0.orientation_rad.yaw), e.position_m.x(), e.position_m.y(),
            e.position_m.z(), aar_geometry::RadToDeg(e.orientation_rad.roll),
            aar_geometry::RadToDeg(e.orientation_rad.pitch),
            aar_geometry::RadToDeg(e.orientation_rad.yaw), r.quality, r.search_shift_px.x(),
            r.search_shift_px.y(), std::sqrt(r.covariance(0, 0)), std::sqrt(r.covariance(1, 1)),
            std::sqrt(r.covariance(2, 2)), aar_geometry::RadToDeg(std::sqrt(r.covariance(3, 3))),
            aar_geometry::RadToDeg(std::sqrt(r.covariance(4, 4))),
            aar_geometry::RadToDeg(std::sqrt(r.covariance(5, 5))));
      }
      sum += e.position_m.norm();
      worst = std::max(worst, e.position_m.norm());
      angle = std::max({angle, std::abs(e.orientation_rad.roll), std::abs(e.orientation_rad.pitch),
                        std::abs(e.orientation_rad.yaw)});
      quality += r.quality, inliers += r.inlier_share, ms += r.time_ms, lines += r.lines;
    }
    const int ok = std::max(1, starts - failures);
    std::printf("%6.1f %7.1f | %8.3f %8.3f %8.3f | %7.3f %7.3f %6d %5.1f | %d\n", t,
                row.position_m.norm(), sum / ok, worst, aar_geometry::RadToDeg(angle), quality / ok,
                inliers / ok, lines / ok, ms / ok, failures);
  }
  return 0;
}
