// The outline alignment (aar_alignment) on rendered frames of the shipped approach, by range:
// from starts off the truth by a fixed position and attitude error in seeded random directions
// (the same for each line model), the error left after alignment, its time, lines and quality;
// with the boom masked out. The contrast line model (the default) and the region model (SRT3D's
// statistics) side by side in one run.
//   bench_alignment [ideal|realistic] [starts per range] [position error m] [attitude error deg]
// Environment: AAR_ALIGN_T (one path time only), AAR_ALIGN_SEARCH (the search radius [px]),
// AAR_ALIGN_SCALES ("4,2,1"), AAR_ALIGN_DUMP (PREFIX: the outline at the truth drawn to
// PREFIX_<t>.png), AAR_ALIGN_VERBOSE (each start's error before and after).
// Then, by range, the start from the images alone (aar_alignment::Acquire from nothing but the
// receiver description's contact attitude): its error, fit, share of the outline seen and time.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <aar_alignment/acquire.h>
#include <aar_alignment/aligner.h>
#include <aar_alignment/boom_parts.h>
#include <aar_description/boom_model.h>
#include <aar_description/boom_parts.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/pose_error.h>
#include <aar_sim/flight_path.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aar_testing/alignment_views.h"
#include "aar_testing/paths.h"
#include "aar_testing/sim_stereo.h"

namespace {

struct Row {
  double sum = 0.0, worst = 0.0, angle = 0.0, quality = 0.0, inliers = 0.0, ms = 0.0;
  int lines = 0, failures = 0;
};

void PrintStart(const Eigen::Isometry3d& truth, const Eigen::Isometry3d& start,
                const aar_alignment::AlignmentResult& r) {
  const auto e0 = aar_geometry::ComputePoseError(truth, start);
  const auto e = aar_geometry::ComputePoseError(truth, r.T_tanker_receiver);
  auto deg = [](double rad) { return aar_geometry::RadToDeg(rad); };
  std::printf(
      "  start x %6.2f %6.2f %6.2f rpy %5.1f %5.1f %5.1f -> x %6.2f %6.2f %6.2f rpy %5.1f %5.1f "
      "%5.1f q %.2f shift %.1f %.1f\n",
      e0.position_m.x(), e0.position_m.y(), e0.position_m.z(), deg(e0.orientation_rad.roll),
      deg(e0.orientation_rad.pitch), deg(e0.orientation_rad.yaw), e.position_m.x(),
      e.position_m.y(), e.position_m.z(), deg(e.orientation_rad.roll), deg(e.orientation_rad.pitch),
      deg(e.orientation_rad.yaw), r.quality, r.search_shift_px.x(), r.search_shift_px.y());
}

// `starts` alignments from the truth moved by the errors in directions drawn with `seed`.
Row Measure(const aar_alignment::OutlineAligner& aligner, aar_alignment::AlignmentInput in,
            const Eigen::Isometry3d& truth, int starts, double position_error,
            double attitude_error, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss;
  auto direction = [&]() {
    return Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  };
  Row row;
  for (int s = 0; s < starts; ++s) {
    Eigen::Isometry3d start = truth;
    start.translation() += position_error * direction();
    start.linear() =
        Eigen::AngleAxisd(attitude_error, direction()).toRotationMatrix() * start.linear();
    in.T_tanker_receiver_predicted = start;
    const aar_alignment::AlignmentResult r = aligner.Align(in);
    if (!r.valid) {
      ++row.failures;
      std::printf("  %s\n", r.error.c_str());
      continue;
    }
    if (std::getenv("AAR_ALIGN_VERBOSE")) PrintStart(truth, start, r);
    const auto e = aar_geometry::ComputePoseError(truth, r.T_tanker_receiver);
    row.sum += e.position_m.norm();
    row.worst = std::max(row.worst, e.position_m.norm());
    row.angle = std::max({row.angle, std::abs(e.orientation_rad.roll),
                          std::abs(e.orientation_rad.pitch), std::abs(e.orientation_rad.yaw)});
    row.quality += r.quality, row.inliers += r.inlier_share, row.ms += r.time_ms;
    row.lines += r.lines;
  }
  return row;
}

void Dump(const aar_alignment::OutlineAligner& aligner, const aar_alignment::AlignmentInput& in,
          const Eigen::Isometry3d& truth, const std::string& prefix, double t) {
  cv::Mat colour;
  cv::cvtColor(in.left, colour, cv::COLOR_GRAY2BGR);
  for (const auto& c : aligner.model().Contour(in.left_camera, truth, 200)) {
    const cv::Point a(cvRound(c.pixel.x()), cvRound(c.pixel.y()));
    cv::line(colour, a, a + cv::Point(cvRound(6 * c.normal.x()), cvRound(6 * c.normal.y())),
             cv::Scalar(0, 0, 255));
    cv::circle(colour, a, 1, cv::Scalar(0, 255, 0), -1);
  }
  cv::imwrite(prefix + "_" + std::to_string(static_cast<int>(t)) + ".png", colour);
}

aar_alignment::AlignmentOptions OptionsFromEnvironment() {
  aar_alignment::AlignmentOptions options;
  if (const char* radius = std::getenv("AAR_ALIGN_SEARCH"))
    options.search_radius_px = std::atof(radius);
  if (const char* scales = std::getenv("AAR_ALIGN_SCALES")) {  // e.g. "5,3,2,1"
    options.scales.clear();
    for (const char* c = scales; *c;) {
      options.scales.push_back(std::strtod(c, const_cast<char**>(&c)));
      if (*c == ',') ++c;
    }
  }
  return options;
}

// The start from the images alone at each of `times` (the frames' boom masked).
void AcquisitionTable(aar_testing::SimStereo& sim, const aar_sim::FlightPath& path,
                      const std::vector<aar_description::BoomCollisionPart>& boom,
                      const std::vector<double>& times) {
  const aar_alignment::OutlineAligner aligner(sim.world().receiver_mesh());
  const auto c12 = aar_description::LoadReceiverDescription(aar_testing::ModelsDir() + "/c12.yaml");
  std::printf("\nfrom the images alone (Acquire, default options)\n");
  std::printf("%6s %7s | %8s %8s %7s %6s %5s %s\n", "t [s]", "range", "|dx|", "ang max", "quality",
              "seen", "ms", "");
  for (const double t : times) {
    const aar_sim::FlightPathRow row = path.At(t);
    const aar_sim::StereoFrame f =
        sim.world().Render(row, aar_description::DefaultBoomPose(), static_cast<uint64_t>(t * 30));
    aar_alignment::AlignmentInput in;
    in.left = sim.Left(f), in.right = sim.Right(f);
    in.left_camera = aar_testing::LeftCamera(sim.rig());
    in.right_camera = aar_testing::RightCamera(sim.rig());
    in.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(boom, f.T_tanker_links);
    in.T_tanker_receiver_predicted = c12.T_tanker_receiver_contact;  // its attitude only
    const aar_alignment::AcquisitionResult a = aar_alignment::Acquire(aligner, in);
    const auto e =
        aar_geometry::ComputePoseError(f.T_tanker_receiver, a.alignment.T_tanker_receiver);
    const double angle =
        std::max({std::abs(e.orientation_rad.roll), std::abs(e.orientation_rad.pitch),
                  std::abs(e.orientation_rad.yaw)});
    const double seen = a.alignment.outline_lines > 0
                            ? static_cast<double>(a.alignment.lines) / a.alignment.outline_lines
                            : 0.0;
    std::printf("%6.1f %7.1f | %8.3f %8.3f %7.3f %6.2f %5.0f %s\n", t, row.position_m.norm(),
                e.position_m.norm(), aar_geometry::RadToDeg(angle), a.alignment.quality, seen,
                a.time_ms, a.valid ? "" : a.error.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string world = argc > 1 ? argv[1] : "ideal";
  const int starts = argc > 2 ? std::atoi(argv[2]) : 5;
  const double position_error = argc > 3 ? std::atof(argv[3]) : 2.0;
  const double attitude_error = aar_geometry::DegToRad(argc > 4 ? std::atof(argv[4]) : 3.0);
  if ((world != "ideal" && world != "realistic") || starts < 1) {
    std::fprintf(stderr, "bench_alignment: usage: [ideal|realistic] [starts >= 1] [m] [deg]\n");
    return 2;
  }
  aar_testing::SimStereo sim(world == "ideal" ? aar_testing::SimStereo::DefaultWorld()
                                              : aar_testing::RealisticWorld());
  const auto path = aar_sim::FlightPath::Load(aar_testing::DefaultApproachPath());
  const auto boom = aar_description::LoadBoomCollisionParts(aar_testing::LoadBoomModel());
  aar_alignment::AlignmentOptions options = OptionsFromEnvironment();
  const aar_alignment::OutlineAligner contrast(sim.world().receiver_mesh(), options);
  options.line_model = aar_alignment::LineModel::kRegion;
  const aar_alignment::OutlineAligner region(sim.world().receiver_mesh(), options);
  std::printf("world %s, %d starts per range, start error %.2f m and %.2f deg\n", world.c_str(),
              starts, position_error, aar_geometry::RadToDeg(attitude_error));
  std::printf("%6s %7s | %-52s | %-33s\n", "", "", "contrast (default)", "region (SRT3D)");
  std::printf("%6s %7s | %8s %8s %8s %7s %6s %5s %4s | %8s %8s %5s %4s\n", "t [s]", "range",
              "|dx| mean", "|dx| max", "ang max", "quality", "lines", "ms", "fail", "|dx| mean",
              "ang max", "ms", "fail");
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
    if (const char* dump = std::getenv("AAR_ALIGN_DUMP"))
      Dump(contrast, in, f.T_tanker_receiver, dump, t);
    const unsigned seed = 7 + static_cast<unsigned>(t * 10);
    const Row c =
        Measure(contrast, in, f.T_tanker_receiver, starts, position_error, attitude_error, seed);
    const Row r =
        Measure(region, in, f.T_tanker_receiver, starts, position_error, attitude_error, seed);
    const int nc = std::max(1, starts - c.failures), nr = std::max(1, starts - r.failures);
    std::printf("%6.1f %7.1f | %8.3f %8.3f %8.3f %7.3f %6d %5.1f %4d | %8.3f %8.3f %5.1f %4d\n", t,
                row.position_m.norm(), c.sum / nc, c.worst, aar_geometry::RadToDeg(c.angle),
                c.quality / nc, c.lines / nc, c.ms / nc, c.failures, r.sum / nr,
                aar_geometry::RadToDeg(r.angle), r.ms / nr, r.failures);
  }
  AcquisitionTable(sim, path, boom, times);
  return 0;
}
