#include <gtest/gtest.h>

#include <random>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/primitives.h>
#include <aar_geometry/receiver_reference.h>
#include <ros/package.h>

#include "aar_registration/icp.h"

namespace aar_registration {
namespace {

using aar_geometry::ReferenceCloud;
using aar_geometry::ReferenceModelOptions;
using aar_geometry::SampleReceiver;
using aar_geometry::Shell;
using aar_geometry::VisibilityTester;

const aar_geometry::TriangleMesh& Receiver() {
  static const aar_geometry::TriangleMesh mesh =
      aar_geometry::LoadMesh(ros::package::getPath("aar_description") + "/models/receiver.obj");
  return mesh;
}

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

// Random rigid motions up to 10 deg and 2 m applied to a sampled receiver with 1 mm noise are
// recovered to under 1 mm and 0.01 deg. From identity, so correspondences may be up to ~3 m
// apart at first; the pipeline seeds much closer.
void CheckRecovery(IcpMetric metric) {
  ReferenceModelOptions sampling;
  const ReferenceCloud target = SampleReceiver(Receiver(), sampling);
  IcpOptions options;
  options.metric = metric;
  options.max_correspondence_distance = 4.0;
  options.max_iterations = 100;
  // Point-to-plane steps overshoot far from the solution: a rise of the RMS must not stop it.
  options.stop_on_rms_rise = metric == IcpMetric::kPointToPoint;
  options.min_rms_improvement = 1e-5;  // [m] the thesis's 0 would run to the cap here
  Icp icp(options);
  icp.SetTarget(target.points, target.normals);

  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();  // T_target_source
    T_true.linear() = Eigen::AngleAxisd((5.0 + 5.0 * std::abs(unit(rng))) * M_PI / 180.0, axis)
                          .toRotationMatrix();
    T_true.translation() =
        Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized() * (1.0 + std::abs(unit(rng)));
    std::vector<Eigen::Vector3d> source;
    for (size_t i = 0; i < target.size(); i += 8) {
      source.push_back(T_true.inverse() * target.points[i] +
                       Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
    const RegistrationResult r = icp.Align(source, Eigen::Isometry3d::Identity());
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_TRUE(r.converged);
    EXPECT_LT((r.T_target_source.translation() - T_true.translation()).norm(), 0.001);
    EXPECT_LT(AngleDeg(r.T_target_source.linear(), T_true.linear()), 0.01);
    EXPECT_GT(r.fitness, 0.99);
    EXPECT_LT(r.rms, 0.003);
    std::printf("[ icp ] %s trial %d: %d iterations, rms %.4f m, error %.3g m / %.3g deg\n",
                metric == IcpMetric::kPointToPoint   ? "point-to-point"
                : metric == IcpMetric::kPointToPlane ? "point-to-plane"
                                                     : "generalized (PCL)",
                trial, r.iterations, r.rms,
                (r.T_target_source.translation() - T_true.translation()).norm(),
                AngleDeg(r.T_target_source.linear(), T_true.linear()));
  }
}

TEST(Icp, PointToPointRecoversRigidMotions) { CheckRecovery(IcpMetric::kPointToPoint); }
TEST(Icp, PointToPlaneRecoversRigidMotions) { CheckRecovery(IcpMetric::kPointToPlane); }
TEST(Icp, GeneralizedPclRecoversRigidMotions) { CheckRecovery(IcpMetric::kGeneralizedPcl); }

// Stereo scatters each point along its camera ray, zero-mean: sigma_Z = Z^2 sigma_d / (f b). The
// receiver's visible surface seen from the default rig at contact (17 m from the left camera:
// region C), sampled apart from its shelled reference, scattered along the rays by `sigma_d` [px]
// on the shipped rig (f b = 554 px m; 0.35 px, what bench_disparity measures on the receiver with
// the suite's sensor noise, is sigma_Z = 0.18 m) and registered from the truth with tracking's ICP
// settings: the estimate's offset along the line of sight [m], averaged over `trials` draws.
double OffsetAlongTheLineOfSight(IcpMetric metric, double sigma_d, int trials) {
  const Eigen::Vector3d eye(15.0, 0.75, 7.2), right_eye(15.0, 1.25, 7.2);  // receiver frame
  ReferenceModelOptions dense;
  dense.points_per_m2 = 127.0;  // the occlusion stage's dynamic reference
  const VisibilityTester visibility(Receiver());
  const ReferenceCloud target =
      Shell(SampleReceiver(Receiver(), dense), visibility, {eye, right_eye}, 0.01);
  ReferenceModelOptions other = dense;  // the sensed surface: other points than the reference's
  other.seed = 2;
  const ReferenceCloud surface =
      Shell(SampleReceiver(Receiver(), other), visibility, {eye, right_eye}, 0.01);
  IcpOptions options;  // config/experiments/tracking.yaml's
  options.metric = metric;
  options.max_correspondence_distance = 1.0;
  options.min_rms_improvement = 1e-5;
  options.stop_on_rms_rise = false;
  options.stereo.ray_sigma_coefficient = 0.35 / 554.0;
  Icp icp(options);
  icp.SetTarget(target.points, target.normals);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : surface.points) centroid += p;
  const Eigen::Vector3d line_of_sight = (centroid / surface.size() - eye).normalized();
  double mean = 0.0;
  for (int trial = 0; trial < trials; ++trial) {
    std::mt19937_64 rng(100 + trial);
    std::normal_distribution<double> unit(0.0, 1.0);
    std::vector<Eigen::Vector3d> sensed;
    for (size_t i = 0; i < surface.size() && sensed.size() < 3000; i += 2) {
      const Eigen::Vector3d ray = surface.points[i] - eye;
      sensed.push_back(surface.points[i] +
                       sigma_d / 554.0 * ray.squaredNorm() * unit(rng) * ray.normalized());
    }
    const RegistrationResult r = icp.Align(sensed, Eigen::Isometry3d::Identity(), &eye);
    // The estimate's offset: the inverse of the transform that maps the sensed points back.
    mean += r.T_target_source.inverse().translation().dot(line_of_sight) / trials;
  }
  return mean;
}

// What zero-mean scatter along the rays does to the registered range: the offset with 0.35 px of
// scatter less the offset without. Pairs found along the rays and weighted by the noise along
// them (stereo rays) barely move; nearest-point pairs with the same plane residual and no weights
// (point-to-plane) are pulled by decimetres.
TEST(Icp, StereoRaysLeaveTheRangeUnbiasedByScatterAlongTheRays) {
  double shift[3] = {0, 0, 0};
  const IcpMetric metrics[3] = {IcpMetric::kStereoRays, IcpMetric::kPointToPoint,
                                IcpMetric::kPointToPlane};
  for (int m = 0; m < 3; ++m) {
    shift[m] = OffsetAlongTheLineOfSight(metrics[m], 0.35, 4) -
               OffsetAlongTheLineOfSight(metrics[m], 0.0, 1);
  }
  std::printf(
      "[ icp ] range offset made by 0.35 px of scatter along the rays [m]: stereo rays %+.4f, "
      "point-to-point %+.4f, point-to-plane %+.4f\n",
      shift[0], shift[1], shift[2]);
  // Measured: +0.0019, -0.0051 and -0.1305 m. Without the weights (ray_sigma_coefficient 0: pairs
  // along the rays, every residual alike) the scatter makes +0.0055 m, and this fails.
  EXPECT_LT(std::abs(shift[0]), 0.003);
  EXPECT_LT(std::abs(shift[0]), std::abs(shift[1]));
  EXPECT_GT(std::abs(shift[2]), 0.10);
}

TEST(Icp, StereoRaysNeedTheCamera) {
  IcpOptions options;
  options.metric = IcpMetric::kStereoRays;
  Icp icp(options);
  const ReferenceCloud target = SampleReceiver(Receiver(), ReferenceModelOptions{});
  EXPECT_THROW(icp.SetTarget(target.points), std::invalid_argument);  // no normals
  icp.SetTarget(target.points, target.normals);
  try {
    icp.Align(target.points, Eigen::Isometry3d::Identity());
    ADD_FAILURE() << "no error without the camera";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "stereo-ray ICP needs the camera's position (source_eye)");
  }
  for (const double bad : {-1.0, std::nan("")}) {
    IcpOptions o = options;
    o.stereo.ray_sigma_coefficient = bad;
    EXPECT_THROW(Icp{o}, std::invalid_argument);
    o = options;
    o.stereo.ray_reach = bad;
    EXPECT_THROW(Icp{o}, std::invalid_argument);
    o = options;
    o.stereo.plane_sigma = bad;
    EXPECT_THROW(Icp{o}, std::invalid_argument);
  }
}

TEST(Icp, PointToPlaneRefusesAPlane) {
  // A flat target leaves in-plane motion unconstrained: not converged, rather than a made-up
  // answer.
  std::vector<Eigen::Vector3d> plane, normals;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      plane.emplace_back(0.1 * i, 0.1 * j, 0.0);
      normals.emplace_back(0, 0, 1);
    }
  IcpOptions o;
  o.metric = IcpMetric::kPointToPlane;
  Icp icp(o);
  icp.SetTarget(plane, normals);
  std::vector<Eigen::Vector3d> source;
  for (const auto& p : plane) source.push_back(p + Eigen::Vector3d(0.7, -0.4, 0.05));
  EXPECT_FALSE(icp.Align(source, Eigen::Isometry3d::Identity()).converged);
}

TEST(Icp, StatisticsDescribeTheReturnedTransform) {
  const ReferenceCloud target = SampleReceiver(Receiver(), ReferenceModelOptions{});
  IcpOptions o;
  o.max_iterations = 3;  // stops while still improving
  o.max_correspondence_distance = 4.0;
  Icp icp(o);
  icp.SetTarget(target.points);
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.translation() << 0.8, -0.5, 0.3;
  std::vector<Eigen::Vector3d> source;
  for (size_t i = 0; i < target.size(); i += 16) source.push_back(offset * target.points[i]);
  const RegistrationResult r = icp.Align(source, Eigen::Isometry3d::Identity());
  ASSERT_FALSE(r.converged);
  // Brute-force RMS of the returned transform.
  double sum = 0.0;
  int n = 0;
  for (const auto& s : source) {
    const Eigen::Vector3d p = r.T_target_source * s;
    double best = 1e18;
    for (const auto& q : target.points) best = std::min(best, (p - q).squaredNorm());
    if (best <= 16.0) sum += best, ++n;
  }
  EXPECT_EQ(n, r.correspondences);
  EXPECT_NEAR(std::sqrt(sum / n), r.rms, 1e-9);
}

TEST(Icp, BadInputs) {
  Icp icp{IcpOptions{}};
  EXPECT_THROW(icp.Align({{0, 0, 0}}, Eigen::Isometry3d::Identity()),
               std::invalid_argument);  // no target
  EXPECT_THROW(icp.SetTarget({}), std::invalid_argument);
  EXPECT_THROW(icp.SetTarget({{0, 0, std::nan("")}}), std::invalid_argument);
  IcpOptions plane;
  plane.metric = IcpMetric::kPointToPlane;
  EXPECT_THROW(Icp{plane}.SetTarget({{0, 0, 0}}), std::invalid_argument);  // no normals
  IcpOptions bad;
  bad.max_iterations = 0;
  EXPECT_THROW(Icp{bad}, std::invalid_argument);

  const ReferenceCloud target = SampleReceiver(Receiver(), ReferenceModelOptions{});
  icp.SetTarget(target.points);
  EXPECT_FALSE(icp.Align({}, Eigen::Isometry3d::Identity()).converged);  // empty source
  // NaN points are skipped; too few points: not converged, no throw.
  std::vector<Eigen::Vector3d> nan_and_far = {{std::nan(""), 0, 0}, {500, 0, 0}, {501, 0, 0}};
  RegistrationResult r = icp.Align(nan_and_far, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.correspondences, 2);  // no gate (thesis): every finite point pairs
  // Behind a 1 m gate, far-off points have no correspondence.
  IcpOptions gated;
  gated.max_correspondence_distance = 1.0;
  Icp gated_icp(gated);
  gated_icp.SetTarget(target.points);
  for (int i = 0; i < 20; ++i) nan_and_far.push_back(Eigen::Vector3d(500, i, 0));
  r = gated_icp.Align(nan_and_far, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.correspondences, 0);
  IcpOptions negative;
  negative.max_correspondence_distance = -1.0;
  EXPECT_THROW(Icp{negative}, std::invalid_argument);
  negative = {};
  negative.min_rms_improvement = -1e-3;
  EXPECT_THROW(Icp{negative}, std::invalid_argument);
}

// Section 3.6: ICP stops when the RMS stops falling, at most 30 iterations, every point paired.
// A cloud with a tenth of its points 20 m off (boom-like outliers): the thesis's ICP pairs them
// all. With room to run (the thesis caps at 30) it stops once the RMS no longer falls; capped one
// iteration earlier it had not stopped, and its RMS was higher.
TEST(Icp, ThesisStopsWhenTheRmsStopsFallingWithEveryPointPaired) {
  const ReferenceCloud target = SampleReceiver(Receiver(), ReferenceModelOptions{});
  std::vector<Eigen::Vector3d> source;
  const Eigen::Isometry3d T = aar_geometry::MakeTransform({0.3, -0.2, 0.1}, {0.02, -0.01, 0.03});
  for (size_t i = 0; i < target.size(); i += 10) {
    source.push_back(T * target.points[i]);
    if (i % 100 == 0) source.push_back(Eigen::Vector3d(20.0, 0.0, 5.0) + target.points[i] * 0.1);
  }
  IcpOptions thesis;
  thesis.max_iterations = 1000;
  Icp icp(thesis);
  icp.SetTarget(target.points);
  const RegistrationResult r = icp.Align(source, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.correspondences, static_cast<int>(source.size()));
  ASSERT_LT(r.iterations, thesis.max_iterations);
  ASSERT_GT(r.iterations, 1);
  thesis.max_iterations = r.iterations - 1;
  Icp capped(thesis);
  capped.SetTarget(target.points);
  const RegistrationResult before = capped.Align(source, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(before.converged) << before.iterations << " " << before.rms << " " << r.rms;
  EXPECT_GE(before.rms, r.rms);
}

TEST(ReferenceModel, ShelledReceiverHasNoUndersideFromAbove) {
  const ReferenceCloud dense = SampleReceiver(Receiver(), ReferenceModelOptions{});
  EXPECT_GT(dense.size(), 50000u);
  const VisibilityTester tester(Receiver());
  // Cameras about 16 m ahead of and 7 m above the receiver, as at contact, 0.5 m apart.
  const ReferenceCloud shelled = Shell(dense, tester, {{15, 0.75, 7}, {15, 1.25, 7}}, 0.01);
  EXPECT_GT(shelled.size(), dense.size() / 5);
  EXPECT_LT(shelled.size(), dense.size() / 2);
  for (size_t i = 0; i < shelled.size(); ++i) {
    EXPECT_GT(shelled.normals[i].dot(Eigen::Vector3d(15, 1, 7) - shelled.points[i]), 0.0);
  }
  const ReferenceCloud wings_nose = shelled.Select({"left_wing", "right_wing", "nose"});
  EXPECT_GT(wings_nose.size(), shelled.size() / 4);
  for (int part : wings_nose.parts) {
    const std::string& name = wings_nose.part_names[part];
    EXPECT_TRUE(name == "left_wing" || name == "right_wing" || name == "nose") << name;
  }
  EXPECT_THROW(shelled.Select({"canard"}), std::invalid_argument);
}

}  // namespace
}  // namespace aar_registration
