// Issue 27 on rendered frames: the outline alignment (aar_alignment) recovers a receiver pose
// perturbed by 2 m and 3 deg at 170 m in the ideal and the realistic world, masking the boom
// matters where it crosses the receiver, and the tracker refuses a start whose outline does not
// fit the images (a self-consistent wrong pose stereo alone would accept).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include <aar_alignment/aligner.h>
#include <aar_alignment/boom_parts.h>
#include <aar_description/boom_model.h>
#include <aar_description/boom_parts.h>
#include <aar_description/receiver_description.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_registration/registrar.h>
#include <aar_sim/flight_path.h>

#include "aar_testing/alignment_views.h"
#include "aar_testing/paths.h"
#include "aar_testing/sim_stereo.h"
#include "aar_testing/suite_approach.h"

namespace aar_testing {
namespace {

struct Errors {
  double mean_position = 0.0, max_position = 0.0, max_angle_deg = 0.0, min_quality = 1.0;
  double lines = 0.0;  // mean usable lines
  int failures = 0;
};

// The frame at path time `t` rendered in `world`, aligned from `starts` starts off the truth by
// `position` [m] and `attitude` [rad] in seeded random directions (with a prediction covariance
// of that size, as a tracker would give), the boom masked or not.
Errors AlignFromPerturbedStarts(const aar_sim::WorldOptions& world, double t, int starts,
                                double position, double attitude, bool mask_boom) {
  SimStereo sim(world);
  const auto path = aar_sim::FlightPath::Load(DefaultApproachPath());
  const aar_sim::StereoFrame f = sim.world().Render(path.At(t), aar_description::DefaultBoomPose(),
                                                    static_cast<uint64_t>(t * 10));
  aar_alignment::AlignmentInput in;
  in.left = sim.Left(f), in.right = sim.Right(f);
  in.left_camera = LeftCamera(sim.rig()), in.right_camera = RightCamera(sim.rig());
  if (mask_boom) {
    in.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(
        aar_description::LoadBoomCollisionParts(LoadBoomModel()), f.T_tanker_links);
  }
  aar_alignment::Vector6d sigma;
  sigma << Eigen::Vector3d::Constant(position), Eigen::Vector3d::Constant(attitude);
  in.prediction_covariance = sigma.cwiseAbs2().asDiagonal();
  const aar_alignment::OutlineAligner aligner(sim.world().receiver_mesh());
  std::mt19937 rng(27);
  std::normal_distribution<double> gauss;
  auto direction = [&] { return Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized(); };
  Errors e;
  for (int s = 0; s < starts; ++s) {
    in.T_tanker_receiver_predicted = f.T_tanker_receiver;
    in.T_tanker_receiver_predicted.translation() += position * direction();
    in.T_tanker_receiver_predicted.linear() =
        Eigen::AngleAxisd(attitude, direction()).toRotationMatrix() * f.T_tanker_receiver.linear();
    const aar_alignment::AlignmentResult r = aligner.Align(in);
    if (!r.valid) {
      ++e.failures;
      continue;
    }
    const auto error = aar_geometry::ComputePoseError(f.T_tanker_receiver, r.T_tanker_receiver);
    e.mean_position += error.position_m.norm() / starts;
    e.max_position = std::max(e.max_position, error.position_m.norm());
    e.max_angle_deg =
        std::max({e.max_angle_deg, std::abs(error.orientation_rad.roll),
                  std::abs(error.orientation_rad.pitch), std::abs(error.orientation_rad.yaw)});
    e.min_quality = std::min(e.min_quality, r.quality);
    e.lines += static_cast<double>(r.lines) / starts;
  }
  e.max_angle_deg *= 180.0 / M_PI;
  return e;
}

void Print(const char* what, const Errors& e) {
  std::printf(
      "[ %s ] mean %.3f m, max %.3f m, max angle %.3f deg, min fit %.2f, %.0f lines, %d failed\n",
      what, e.mean_position, e.max_position, e.max_angle_deg, e.min_quality, e.lines, e.failures);
}

TEST(OutlineAlignment, RecoversAPosePerturbedBy2mAnd3DegAt170m) {
  const double deg = M_PI / 180.0;
  const Errors ideal =
      AlignFromPerturbedStarts(SimStereo::DefaultWorld(), 0.5, 8, 2.0, 3 * deg, true);
  Print("ideal, 170.6 m", ideal);
  const Errors realistic = AlignFromPerturbedStarts(RealisticWorld(), 0.5, 8, 2.0, 3 * deg, true);
  Print("realistic, 170.6 m", realistic);
  // Measured: ideal mean 0.344 m, max 0.672 m, 0.200 deg, fit >= 0.87; realistic mean 0.375 m,
  // max 0.896 m, 0.271 deg, fit >= 0.81. Most of it lies along the line of sight, where the
  // outline's own sigma at 170 m is about 0.7 m (its covariance).
  for (const Errors* e : {&ideal, &realistic}) {
    EXPECT_EQ(e->failures, 0);
    EXPECT_LT(e->mean_position, 0.45);
    EXPECT_LT(e->max_position, 1.0);
    EXPECT_LT(e->max_angle_deg, 0.35);
    EXPECT_GT(e->min_quality, 0.75);
  }
}

// Near contact (36.5 m) the boom crosses the receiver: the lines that cross its projection are
// left out, and the alignment holds from a tracker-sized error. (Measured: unmasked, the boom's
// edges do not pull it measurably on the default approach, 0.065 against 0.066 m mean; the
// mask is kept for what lies behind the boom, which the cameras cannot see.)
TEST(OutlineAlignment, NearContactTheBoomIsMaskedAndTheAlignmentHolds) {
  const double deg = M_PI / 180.0;
  const Errors masked =
      AlignFromPerturbedStarts(SimStereo::DefaultWorld(), 50.5, 6, 0.15, 1 * deg, true);
  const Errors unmasked =
      AlignFromPerturbedStarts(SimStereo::DefaultWorld(), 50.5, 6, 0.15, 1 * deg, false);
  Print("contact, boom masked", masked);
  Print("contact, boom not masked", unmasked);
  // Measured: masked 0.007 m mean, 0.010 m max, 0.026 deg, 363 lines against 400 unmasked.
  EXPECT_EQ(masked.failures, 0);
  EXPECT_LT(masked.max_position, 0.02);
  EXPECT_LT(masked.max_angle_deg, 0.1);
  EXPECT_LT(masked.lines, unmasked.lines - 10);
}

// The RQ-4 (a 39.9 m span, 2.4 times the C-12's box) in region B of its approach, aligned from
// its truth by the default outline mask (320 px across the receiver's box, up to 4 mask px per
// image px) and by flight's (1408 px, one per image px). At 55 to 65 m the coarse mask's box is
// about 3 image px per mask px, and silhouette edges that the nacelle hides pass for outline: the
// estimate too close and nose down (docs/INTEGRITY.md, the outline's mask). Mean x error (along
// the line of sight, + too close) and pitch error over the frames.
TEST(OutlineAlignment, TheRq4IsAlignedWithoutBiasWithAMaskAtTheImagesResolution) {
  aar_sim::WorldOptions world = SimStereo::DefaultWorld();
  world.receiver = aar_description::LoadReceiverDescription(ModelsDir() + "/rq4.yaml");
  SimStereo sim(world);
  const auto path = aar_sim::FlightPath::Load(ConfigDir() + "/flight_paths/approach_rq4.csv");
  struct Bias {
    double x = 0.0, pitch_deg = 0.0;
  };
  Bias coarse, fine;
  int frames = 0;
  for (const double range : {55.0, 60.0, 65.0}) {
    const aar_sim::FlightPathRow* row = &path.rows().front();
    for (const auto& r : path.rows())
      if (std::abs(r.position_m.norm() - range) < std::abs(row->position_m.norm() - range))
        row = &r;
    const aar_sim::StereoFrame f =
        sim.world().Render(*row, aar_description::DefaultBoomPose(), frames);
    aar_alignment::AlignmentInput in;
    in.left = sim.Left(f), in.right = sim.Right(f);
    in.left_camera = LeftCamera(sim.rig()), in.right_camera = RightCamera(sim.rig());
    in.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(
        aar_description::LoadBoomCollisionParts(LoadBoomModel()), f.T_tanker_links);
    in.T_tanker_receiver_predicted = f.T_tanker_receiver;
    aar_alignment::Vector6d sigma;  // a weak prior: the images decide
    sigma << Eigen::Vector3d::Constant(10.0), Eigen::Vector3d::Constant(0.2);
    in.prediction_covariance = sigma.cwiseAbs2().asDiagonal();
    for (Bias* b : {&coarse, &fine}) {
      aar_alignment::AlignmentOptions o;
      if (b == &fine) o.mask_size = 1408, o.mask_max_scale = 1.0;
      const aar_alignment::OutlineAligner a(sim.world().receiver_mesh(), o);
      const aar_alignment::AlignmentResult r = a.Align(in);
      ASSERT_TRUE(r.valid) << r.error;
      const auto e = aar_geometry::ComputePoseError(f.T_tanker_receiver, r.T_tanker_receiver);
      b->x += e.position_m.x() / 3.0;
      b->pitch_deg += e.orientation_rad.pitch * 180.0 / M_PI / 3.0;
    }
    ++frames;
  }
  std::printf(
      "[ rq4, 55-65 m ] mask 320: x %+.3f m, pitch %+.3f deg; mask 1408 at 1 px: x %+.3f m, "
      "pitch %+.3f deg\n",
      coarse.x, coarse.pitch_deg, fine.x, fine.pitch_deg);
  // Measured: mask 320 x +0.321 m, pitch -0.118 deg; mask 1408 at one px x +0.016 m, pitch
  // -0.016 deg.
  EXPECT_GT(coarse.x, 0.2);
  EXPECT_LT(coarse.pitch_deg, -0.08);
  EXPECT_LT(std::abs(fine.x), 0.05);
  EXPECT_LT(std::abs(fine.pitch_deg), 0.05);
}

// The default approach's frame at 0.5 s (170 m), rendered, as the registrar's outline input.
struct FarFrame {
  SimStereo sim;
  aar_sim::StereoFrame f;
  aar_registration::OutlineFrame frame;

  explicit FarFrame(const aar_sim::WorldOptions& world = SimStereo::DefaultWorld()) : sim(world) {
    f = sim.world().Render(aar_sim::FlightPath::Load(DefaultApproachPath()).At(0.5),
                           aar_description::DefaultBoomPose(), 5);
    frame.left = sim.Left(f), frame.right = sim.Right(f);
    frame.left_camera = LeftCamera(sim.rig()), frame.right_camera = RightCamera(sim.rig());
  }
  const aar_geometry::TriangleMesh& mesh() { return sim.world().receiver_mesh(); }
  // The receiver's pose moved along the line of sight to `range` [m] from the tanker's origin.
  Eigen::Isometry3d Short(double range) const {
    Eigen::Isometry3d T = f.T_tanker_receiver;
    T.translation() *= range / T.translation().norm();
    return T;
  }
};

// Stereo alone cannot tell a self-consistent wrong pose: a cloud that is the receiver's own shape
// placed 140 m short of it registers perfectly and starts a track. The outline in the images,
// where the receiver is 170 m out, refuses that start.
TEST(OutlineAlignment, AStartWhoseOutlineDoesNotFitIsRefused) {
  FarFrame far;
  const aar_geometry::TriangleMesh& mesh = far.mesh();
  const Eigen::Isometry3d wrong = far.Short(30.0);  // 30 m out, 140 m short
  std::vector<Eigen::Vector3d> cloud;
  for (const auto& p : aar_geometry::SampleReceiver(mesh, {}).points) cloud.push_back(wrong * p);
  aar_registration::OutlineFrame& frame = far.frame;
  frame.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(
      aar_description::LoadBoomCollisionParts(LoadBoomModel()), far.f.T_tanker_links);
  for (const bool outline : {false, true}) {
    aar_registration::RegistrarOptions o;
    o.reference = aar_registration::ReferenceKind::kDense;
    o.track = true;
    o.outline.enabled = outline;
    aar_registration::Registrar registrar(o);
    registrar.BuildStaticReference(mesh, {});
    registrar.SetOutlineModel(mesh);
    const aar_registration::RegistrarResult r = registrar.Register(cloud, 1.0, &frame);
    std::printf("[ outline %s ] registered %d, track %s, valid %d, %s\n", outline ? "on" : "off",
                r.registered, aar_registration::ToString(r.track.outcome), r.valid,
                r.outline_note.c_str());
    ASSERT_TRUE(r.registered);  // stereo alone: a perfect fit
    if (!outline) {
      EXPECT_EQ(r.track.outcome, aar_registration::TrackOutcome::kStarted);
      EXPECT_TRUE(r.valid);
    } else {
      EXPECT_FALSE(r.valid);
      EXPECT_NE(r.track.outcome, aar_registration::TrackOutcome::kStarted);
      EXPECT_NE(r.outline_note.find("start refused"), std::string::npos) << r.outline_note;
      EXPECT_EQ(r.error, r.outline_note);  // the frame's miss names the refused start
    }
  }
}

// A start whose attitude is outside the formation's envelope is refused, however well it fits:
// here the envelope's centre (the nominal attitude) is put 30 deg nose up of the receiver, so
// the receiver's true pose, registered and aligned perfectly, is 30 deg outside it.
TEST(OutlineAlignment, AStartOutsideTheAttitudeEnvelopeIsRefused) {
  FarFrame far;
  const aar_geometry::TriangleMesh& mesh = far.mesh();
  std::vector<Eigen::Vector3d> cloud;
  for (const auto& p : aar_geometry::SampleReceiver(mesh, {}).points)
    cloud.push_back(far.f.T_tanker_receiver * p);
  for (const double envelope_deg : {0.0, 15.0}) {
    aar_registration::RegistrarOptions o;
    o.reference = aar_registration::ReferenceKind::kDense;
    o.track = true;
    o.outline.enabled = true;
    o.T_tanker_receiver_nominal = far.f.T_tanker_receiver;
    o.T_tanker_receiver_nominal.linear() *=
        Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).matrix();
    o.integrity.attitude_envelope_deg = envelope_deg;
    aar_registration::Registrar registrar(o);
    registrar.BuildStaticReference(mesh, {});
    registrar.SetOutlineModel(mesh);
    const aar_registration::RegistrarResult r = registrar.Register(cloud, 1.0, &far.frame);
    // Measured: refused at 29.88 deg (the alignment within 0.12 deg of the truth).
    std::printf("[ envelope %.0f deg ] track %s, valid %d, %s\n", envelope_deg,
                aar_registration::ToString(r.track.outcome), r.valid, r.outline_note.c_str());
    if (envelope_deg == 0.0) {
      EXPECT_TRUE(r.valid) << r.outline_note;
      EXPECT_EQ(r.track.outcome, aar_registration::TrackOutcome::kStarted);
      continue;
    }
    EXPECT_FALSE(r.valid);
    EXPECT_NE(r.outline_note.find("start refused: seed 1: attitude 29."), std::string::npos)
        << r.outline_note;
    EXPECT_NE(r.outline_note.find("> envelope 15 deg"), std::string::npos) << r.outline_note;
  }
}

// Clutter denser than a far receiver (on suite approaches 1004 and 1007 tracking_robust's region
// A error averages 43 and 88 m): the receiver's own shape 140 m short, beside the receiver's
// points where it is, four times sparser. The densest ball picks the clutter; its start is
// refused, and the next seed, the densest ball outside the refused registration's, starts the
// track at the receiver in the same frame. With one seed per frame the frame stays without a
// track.
TEST(OutlineAlignment, ARefusedStartIsTriedAgainFromTheNextDensestBall) {
  FarFrame far;
  const aar_geometry::TriangleMesh& mesh = far.mesh();
  const aar_sim::StereoFrame& f = far.f;
  const Eigen::Isometry3d clutter = far.Short(30.0);
  const auto samples = aar_geometry::SampleReceiver(mesh, {}).points;
  std::vector<Eigen::Vector3d> cloud;
  for (size_t i = 0; i < samples.size(); ++i) {
    cloud.push_back(clutter * samples[i]);
    if (i % 4 == 0) cloud.push_back(f.T_tanker_receiver * samples[i]);
  }
  for (const int candidates : {1, 3}) {
    aar_registration::RegistrarOptions o;
    o.reference = aar_registration::ReferenceKind::kDense;
    o.track = true;
    o.seed_points = aar_registration::SeedPoints::kDensestBall;
    o.icp.max_correspondence_distance = 1.0;
    o.outline.enabled = true;
    o.outline.start_candidates = candidates;
    aar_registration::Registrar registrar(o);
    registrar.BuildStaticReference(mesh, {});
    registrar.SetOutlineModel(mesh);
    const aar_registration::RegistrarResult r = registrar.Register(cloud, 1.0, &far.frame);
    const auto e = aar_geometry::ComputePoseError(f.T_tanker_receiver, r.T_tanker_receiver);
    std::printf("[ %d seeds ] track %s, valid %d, error %.3f m, %s\n", candidates,
                aar_registration::ToString(r.track.outcome), r.valid, e.position_m.norm(),
                r.outline_note.c_str());
    if (candidates == 1) {
      EXPECT_FALSE(r.valid);
      EXPECT_NE(r.outline_note.find("start refused: seed 1"), std::string::npos) << r.outline_note;
    } else {
      ASSERT_TRUE(r.valid) << r.outline_note;
      EXPECT_EQ(r.track.outcome, aar_registration::TrackOutcome::kStarted);
      EXPECT_NE(r.outline_note.find("started from seed 2"), std::string::npos) << r.outline_note;
      EXPECT_LT(e.position_m.norm(), 1.0);
    }
  }
}

// Far out stereo may give a receiver nothing to start from (behind the boom's tube, or a few
// dozen points lost to culling): with no sensed points at all, the start comes from the images
// alone (the silhouette at the receiver description's contact attitude searched over the left
// image, then aligned in both), in the ideal and the realistic world. Without image starts the
// frame is refused.
TEST(OutlineAlignment, WithoutStereoPointsATrackStartsFromTheImagesAlone) {
  const aar_description::ReceiverDescription c12 =
      aar_description::LoadReceiverDescription(ModelsDir() + "/c12.yaml");
  for (const bool realistic : {false, true}) {
    FarFrame far(realistic ? RealisticWorld() : SimStereo::DefaultWorld());
    far.frame.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(
        aar_description::LoadBoomCollisionParts(LoadBoomModel()), far.f.T_tanker_links);
    for (const bool image_start : {false, true}) {
      aar_registration::RegistrarOptions o;
      o.reference = aar_registration::ReferenceKind::kDense;
      o.T_tanker_receiver_nominal = c12.T_tanker_receiver_contact;
      o.track = true;
      o.outline.enabled = true;
      o.outline.image_start = image_start;
      aar_registration::Registrar registrar(o);
      registrar.BuildStaticReference(far.mesh(), {});
      registrar.SetOutlineModel(far.mesh());
      const aar_registration::RegistrarResult r = registrar.Register({}, 1.0, &far.frame);
      const auto e = aar_geometry::ComputePoseError(far.f.T_tanker_receiver, r.T_tanker_receiver);
      const double angle =
          std::max({std::abs(e.orientation_rad.roll), std::abs(e.orientation_rad.pitch),
                    std::abs(e.orientation_rad.yaw)}) *
          180.0 / M_PI;
      std::printf("[ %s, image start %s ] valid %d, %.3f m, %.3f deg, %.0f ms, %s\n",
                  realistic ? "realistic" : "ideal", image_start ? "on" : "off", r.valid,
                  e.position_m.norm(), angle, r.outline_ms, r.outline_note.c_str());
      if (!image_start) {
        EXPECT_FALSE(r.valid);
        EXPECT_NE(r.outline_note.find("start refused"), std::string::npos) << r.outline_note;
        continue;
      }
      ASSERT_TRUE(r.valid) << r.outline_note;
      EXPECT_EQ(r.track.outcome, aar_registration::TrackOutcome::kStarted);
      EXPECT_NE(r.outline_note.find("started from the images alone"), std::string::npos)
          << r.outline_note;
      // Measured: ideal 0.160 m, 0.100 deg; realistic 1.203 m, 0.369 deg (fit 0.88 and 0.85),
      // mostly along the line of sight, which a single frame's outline fixes to about 1 %.
      EXPECT_LT(e.position_m.norm(), 1.3);
      EXPECT_LT(angle, 0.45);
    }
  }
}

// Far out over clouds the receiver is seldom the image's best placement for the search: on suite
// approach 7001's first frame (174 m) in the realistic world, with the boom's ruddevator across
// the receiver, the whole image's search places it 15 m off, and that start passes
// image_start_quality (0.7). Stereo's points 50 to 200 m out, most of them on the receiver (62 of
// 79 here), say where to search.
TEST(OutlineAlignment, StereosCueFindsAFarReceiverOverClouds) {
  const std::string path_file = WriteSuiteApproach(7001);
  const aar_sim::FlightPathRow row = aar_sim::FlightPath::Load(path_file).At(0.0);
  std::remove(path_file.c_str());
  SimStereo sim(RealisticWorld());
  const SimStereoFrame f = sim.Run(row, row.boom.value_or(aar_description::DefaultBoomPose()), 0);
  aar_registration::OutlineFrame frame;
  frame.left = sim.Left(f.rendered), frame.right = sim.Right(f.rendered);
  frame.left_camera = LeftCamera(sim.rig()), frame.right_camera = RightCamera(sim.rig());
  frame.boom_parts_in_tanker = aar_alignment::BoomPartsInTanker(
      aar_description::LoadBoomCollisionParts(LoadBoomModel()), f.rendered.T_tanker_links);
  const Eigen::Isometry3d& truth = f.rendered.T_tanker_receiver;
  for (const int cue : {0, 10}) {
    aar_registration::RegistrarOptions o;
    o.reference = aar_registration::ReferenceKind::kDense;
    o.T_tanker_receiver_nominal =
        aar_description::LoadReceiverDescription(ModelsDir() + "/c12.yaml")
            .T_tanker_receiver_contact;
    o.track = true;
    o.outline.enabled = o.outline.image_start = true;
    o.outline.acquisition.min_visible = 0.3;  // the boom hides 40 % of the outline's lines
    o.outline.acquisition.cue_min_points = cue;
    o.outline.alignment.mask_size = 1408, o.outline.alignment.mask_max_scale = 1.0;  // flight's
    aar_registration::Registrar registrar(o);
    registrar.BuildStaticReference(sim.world().receiver_mesh(), {});
    registrar.SetOutlineModel(sim.world().receiver_mesh());
    const aar_registration::RegistrarResult r = registrar.Register(f.points_in_tanker, 1.0, &frame);
    const double error = (r.T_tanker_receiver.translation() - truth.translation()).norm();
    const double angle = aar_geometry::RadToDeg(
        Eigen::AngleAxisd(r.T_tanker_receiver.linear() * truth.linear().transpose()).angle());
    std::printf("[ cue %d ] %zu stereo points, valid %d, %.3f m and %.2f deg off, fit %.2f, %s\n",
                cue, f.points_in_tanker.size(), r.valid, error, angle, r.outline.quality,
                r.outline_note.c_str());
    ASSERT_TRUE(r.valid) << r.outline_note;
    EXPECT_NE(r.outline_note.find("started from the images alone"), std::string::npos)
        << r.outline_note;
    if (cue == 0) {
      EXPECT_GT(error, 10.0);  // measured 14.7 m, 1.4 deg (fit 0.71)
      continue;
    }
    EXPECT_LT(error, 1.0);              // measured 0.835 m
    EXPECT_LT(angle, 0.6);              // measured 0.43 deg
    EXPECT_GT(r.outline.quality, 0.8);  // measured 0.83
  }
}

}  // namespace
}  // namespace aar_testing
