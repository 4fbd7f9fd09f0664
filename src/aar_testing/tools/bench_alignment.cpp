// The outline alignment (aar_alignment) on rendered frames of the shipped approach, by range:
// from starts off the truth by a fixed position and attitude error in seeded random directions
// (the same for each line model), the error left after alignment, its time, lines and quality;
// with the boom masked out. The contrast line model (the default) and the region model (SRT3D's
// statistics) side by side in one run.
//   bench_alignment [ideal|realistic] [starts per range] [position error m] [attitude error deg]
// Environment: AAR_ALIGN_PATH (another flight path), AAR_ALIGN_T (path times, "0,0.5,3"),
// AAR_ALIGN_SEARCH (the search radius [px]), AAR_ALIGN_SCALES ("4,2,1"), AAR_ALIGN_FLIGHT (the
// outline's mask as `flight` draws it), AAR_ALIGN_DUMP (PREFIX: the outline at the truth drawn to
// PREFIX_<t>.png), AAR_ALIGN_VERBOSE (each start's error before and after).
// Then, by range, the start from the images alone (aar_alignment::Acquire from nothing but the
// receiver description's contact attitude; the boom at the path's pose): the outline's fit at the
// truth, the start's error, its attitude's distance from the contact attitude, fit, share of the
// outline seen and time. AAR_ACQ_ONLY: this table alone; AAR_ACQ_MINVIS (min_visible),
// AAR_ACQ_BOTH (both_views);
// AAR_ACQ_CUE (N: cue_min_points, stereo's points from the block matcher of the whole frame, as
// acquisition has them); AAR_ALIGN_RIG2 ("X,Y,Z": a second rig centred there, its views added);
// AAR_ALIGN_RECEIVER (another receiver's description).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
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

// A comma-separated list of numbers ("4,2,1").
std::vector<double> Numbers(const char* text) {
  std::vector<double> out;
  for (const char* c = text; *c;) {
    out.push_back(std::strtod(c, const_cast<char**>(&c)));
    if (*c == ',') ++c;
  }
  return out;
}

aar_alignment::AlignmentOptions OptionsFromEnvironment() {
  aar_alignment::AlignmentOptions options;
  if (const char* radius = std::getenv("AAR_ALIGN_SEARCH"))
    options.search_radius_px = std::atof(radius);
  if (const char* scales = std::getenv("AAR_ALIGN_SCALES"))  // e.g. "5,3,2,1"
    options.scales = Numbers(scales);
  if (std::getenv("AAR_ALIGN_FLIGHT")) options.mask_size = 1408, options.mask_max_scale = 1.0;
  return options;
}

// The largest of an error's roll, pitch and yaw [deg].
double AngleDeg(const aar_geometry::PoseError& e) {
  return aar_geometry::RadToDeg(
      std::max({std::abs(e.orientation_rad.roll), std::abs(e.orientation_rad.pitch),
                std::abs(e.orientation_rad.yaw)}));
}

// One path time as every rig sees it: the frames (stereo's too), the acquisition's input on
// them (its views point into the frames) and stereo's points of every rig (the cue).
struct RigFrames {
  aar_testing::SimStereoFrame first, second;
  aar_alignment::AlignmentInput in;
  std::vector<Eigen::Vector3d> cue;
};

void Capture(aar_testing::SimStereo& sim, aar_testing::SimStereo* second,
             const aar_sim::FlightPathRow& row, uint64_t index,
             const std::vector<aar_description::BoomCollisionPart>& boom, RigFrames& out) {
  const aar_description::BoomPose pose = row.boom.value_or(aar_description::DefaultBoomPose());
  out.first = sim.Run(row, pose, index);
  out.in.left = sim.Left(out.first.rendered), out.in.right = sim.Right(out.first.rendered);
  out.in.left_camera = aar_testing::LeftCamera(sim.rig());
  out.in.right_camera = aar_testing::RightCamera(sim.rig());
  out.in.boom_parts_in_tanker =
      aar_alignment::BoomPartsInTanker(boom, out.first.rendered.T_tanker_links);
  out.cue = out.first.points_in_tanker;
  if (!second) return;
  out.second = second->Run(row, pose, index);
  out.in.extra_views = {
      {second->Left(out.second.rendered), aar_testing::LeftCamera(second->rig())},
      {second->Right(out.second.rendered), aar_testing::RightCamera(second->rig())}};
  out.cue.insert(out.cue.end(), out.second.points_in_tanker.begin(),
                 out.second.points_in_tanker.end());
}

// How many of stereo's points lie 40 to 250 m from the left camera, and within 25 m of the truth.
void PrintCue(const RigFrames& f, const Eigen::Vector3d& eye) {
  int band = 0, on = 0;
  for (const Eigen::Vector3d& p : f.cue) {
    const double r = (p - eye).norm();
    if (r < 40.0 || r > 250.0) continue;
    ++band;
    if ((p - f.first.rendered.T_tanker_receiver.translation()).norm() < 25.0) ++on;
  }
  std::printf("  stereo: %zu points, %d at 40-250 m, %d within 25 m of the receiver\n",
              f.cue.size(), band, on);
}

// The start from the images alone at each of `times` (the frames' boom masked): the outline's
// fit at the truth, and the start's error, its attitude's distance from the contact attitude
// searched at, fit, share of the outline seen and time.
void AcquisitionTable(aar_testing::SimStereo& sim, const aar_sim::FlightPath& path,
                      const std::vector<aar_description::BoomCollisionPart>& boom,
                      const std::vector<double>& times,
                      const aar_alignment::AlignmentOptions& options,
                      const aar_alignment::AcquisitionOptions& acquisition,
                      aar_testing::SimStereo* second = nullptr) {
  const aar_alignment::OutlineAligner aligner(sim.world().receiver_mesh(), options);
  const Eigen::Isometry3d& contact = sim.world_options().receiver.T_tanker_receiver_contact;
  std::printf("\nfrom the images alone (Acquire, min_visible %.2f, cue_min_points %d%s)\n",
              acquisition.min_visible, acquisition.cue_min_points, second ? ", two rigs" : "");
  std::printf("%6s %7s %9s | %8s %8s %9s %7s %6s %5s %s\n", "t [s]", "range", "fit@truth", "|dx|",
              "ang max", "from nom.", "quality", "seen", "ms", "");
  for (const double t : times) {
    const aar_sim::FlightPathRow row = path.At(t);
    RigFrames f;
    Capture(sim, second, row, static_cast<uint64_t>(t * 30), boom, f);
    const Eigen::Isometry3d& truth = f.first.rendered.T_tanker_receiver;
    f.in.T_tanker_receiver_predicted = truth;
    const double truth_fit = aligner.Score(f.in).quality;
    if (acquisition.cue_min_points > 0) PrintCue(f, sim.left_eye());
    f.in.T_tanker_receiver_predicted = contact;  // its attitude only
    const aar_alignment::AcquisitionResult a =
        aar_alignment::Acquire(aligner, f.in, acquisition, f.cue);
    const auto e = aar_geometry::ComputePoseError(truth, a.alignment.T_tanker_receiver);
    const auto nominal = aar_geometry::ComputePoseError(contact, a.alignment.T_tanker_receiver);
    std::printf("%6.1f %7.1f %9.3f | %8.3f %8.3f %9.3f %7.3f %6.2f %5.0f %s\n", t,
                row.position_m.norm(), truth_fit, e.position_m.norm(), AngleDeg(e),
                AngleDeg(nominal), a.alignment.quality, SeenShare(acquisition, a.alignment),
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
  aar_sim::WorldOptions world_options =
      world == "ideal" ? aar_testing::SimStereo::DefaultWorld() : aar_testing::RealisticWorld();
  if (const char* receiver = std::getenv("AAR_ALIGN_RECEIVER"))  // a description's path
    world_options.receiver = aar_description::LoadReceiverDescription(receiver);
  aar_testing::SimStereo sim(world_options);
  const char* path_file = std::getenv("AAR_ALIGN_PATH");
  const auto path =
      aar_sim::FlightPath::Load(path_file ? path_file : aar_testing::DefaultApproachPath());
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
  if (const char* only = std::getenv("AAR_ALIGN_T")) times = Numbers(only);
  aar_alignment::AcquisitionOptions acquisition;
  if (const char* c = std::getenv("AAR_ACQ_MINVIS")) acquisition.min_visible = std::atof(c);
  if (const char* c = std::getenv("AAR_ACQ_CUE")) acquisition.cue_min_points = std::atoi(c);
  acquisition.both_views = std::getenv("AAR_ACQ_BOTH") != nullptr;
  const std::vector<double> aligned = std::getenv("AAR_ACQ_ONLY") ? std::vector<double>() : times;
  for (const double t : aligned) {
    const aar_sim::FlightPathRow row = path.At(t);
    const aar_sim::StereoFrame f = sim.world().Render(
        row, row.boom.value_or(aar_description::DefaultBoomPose()), static_cast<uint64_t>(t * 30));
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
  std::unique_ptr<aar_testing::SimStereo> second;
  if (const char* rig2 = std::getenv("AAR_ALIGN_RIG2")) {  // "X,Y,Z": a second rig's centre
    const std::vector<double> c = Numbers(rig2);
    aar_sim::WorldOptions w = sim.world_options();
    w.rig = aar_sim::MakeStereoRig(w.rig.intrinsics, w.rig.baseline, {c.at(0), c.at(1), c.at(2)});
    second = std::make_unique<aar_testing::SimStereo>(w);
  }
  AcquisitionTable(sim, path, boom, times, contrast.options(), acquisition, second.get());
  return 0;
}
