#include "aar_registration/registrar.h"

#include <gtest/gtest.h>

#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <ros/package.h>

namespace aar_registration {
namespace {

const aar_geometry::TriangleMesh& Receiver() {
  static const aar_geometry::TriangleMesh mesh =
      aar_geometry::LoadMesh(ros::package::getPath("aar_description") + "/models/receiver.obj");
  return mesh;
}

// The receiver at contact, 1 deg off the tanker's attitude, seen as every 8th dense sample.
struct Frame {
  Eigen::Isometry3d T_tanker_receiver =
      aar_geometry::MakeTransform({-35.0, 0.3, -10.19}, {0.01, -0.035, 0.017});
  std::vector<Eigen::Vector3d> sensed;
  Frame() {
    const auto dense =
        aar_geometry::SampleReceiver(Receiver(), aar_geometry::ReferenceModelOptions{});
    for (size_t i = 0; i < dense.size(); i += 8)
      sensed.push_back(T_tanker_receiver * dense.points[i]);
  }
};

TEST(Registrar, StaticReferenceFromTheCentroidSeed) {
  RegistrarOptions options;
  options.reference = ReferenceKind::kDense;
  Registrar registrar(options);
  EXPECT_FALSE(registrar.has_reference());
  const size_t dense = registrar.BuildStaticReference(Receiver(), {});
  EXPECT_GT(dense, 50000u);
  const Frame f;
  const RegistrarResult r = registrar.Register(f.sensed, 10.0);
  ASSERT_TRUE(r.valid) << r.error;
  EXPECT_TRUE(r.icp.converged);
  EXPECT_EQ(r.sensed_points, f.sensed.size());
  EXPECT_EQ(r.reference_points, dense);
  EXPECT_LT((r.T_tanker_receiver.translation() - f.T_tanker_receiver.translation()).norm(), 0.01);

  // Shelled from two eyes ahead and above: a fraction of the dense model.
  options.reference = ReferenceKind::kShelled;
  options.T_tanker_receiver_nominal = f.T_tanker_receiver;
  Registrar shelled(options);
  const size_t seen =
      shelled.BuildStaticReference(Receiver(), {{-20.0, 0.75, -3.0}, {-20.0, 1.25, -3.0}});
  EXPECT_LT(seen, dense / 2);
  EXPECT_GT(seen, dense / 5);
}

TEST(Registrar, MissesSayWhy) {
  RegistrarOptions options;
  options.reference = ReferenceKind::kTopic;
  Registrar registrar(options);
  const Frame f;
  RegistrarResult r = registrar.Register(f.sensed, 1.0);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.error, "no reference model yet");

  std::vector<Eigen::Vector3d> five(5, Eigen::Vector3d::Zero());
  EXPECT_THROW(registrar.SetReference(five, {}), std::invalid_argument);
  EXPECT_FALSE(registrar.has_reference());

  const auto dense =
      aar_geometry::SampleReceiver(Receiver(), aar_geometry::ReferenceModelOptions{});
  registrar.SetReference(dense.points, dense.normals);
  ASSERT_TRUE(registrar.has_reference());
  r = registrar.Register({f.sensed.begin(), f.sensed.begin() + 5}, 1.0);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.error, "cloud has 5 finite points, too few to register");
  // Points far from any reference point (2 km away) give no correspondence: no pose.
  std::vector<Eigen::Vector3d> far = {{2000, 0, 0}, {2000, 30, 0}, {2000, 0, 30}};
  for (int i = 0; i < 20; ++i) far.push_back(Eigen::Vector3d(2000, i, -i));
  r = registrar.Register(far, 1.0);
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.error.find("of the reference: no pose"), std::string::npos) << r.error;
  // A refused reference leaves none behind: the next frame is not registered to a stale one.
  EXPECT_THROW(registrar.SetReference(five, {}), std::invalid_argument);
  EXPECT_EQ(registrar.Register(f.sensed, 2.0).error, "no reference model yet");
}

TEST(Registrar, PreviousEstimateSeedsTheNextFrameWhileRecent) {
  RegistrarOptions options;
  options.reference = ReferenceKind::kDense;
  options.seed = SeedMode::kPrevious;
  options.previous_max_age = 1.0;
  Registrar registrar(options);
  registrar.BuildStaticReference(Receiver(), {});
  const Frame f;
  const RegistrarResult first = registrar.Register(f.sensed, 1.0);  // nothing before: centroid
  ASSERT_TRUE(first.valid && first.icp.converged) << first.error;
  // From the previous estimate the same cloud is already aligned: fewer iterations.
  const RegistrarResult next = registrar.Register(f.sensed, 1.1);
  ASSERT_TRUE(next.valid);
  EXPECT_LT(next.icp.iterations, first.icp.iterations);
  // Older than previous_max_age, or from before the previous frame: the centroid seed again.
  EXPECT_EQ(registrar.Register(f.sensed, 5.0).icp.iterations, first.icp.iterations);
  EXPECT_EQ(registrar.Register(f.sensed, 4.5).icp.iterations, first.icp.iterations);
}

}  // namespace
}  // namespace aar_registration
