#include "aar_occlusion/boom.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include <aar_description/boom_model.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/primitives.h>
#include <aar_geometry/surface_sampling.h>
#include <aar_geometry/weld.h>
#include <ros/package.h>

#include "aar_occlusion/dynamic_reference.h"

namespace aar_occlusion {
namespace {

using aar_geometry::TriangleMesh;

const std::string kModels = ros::package::getPath("aar_description") + "/models";

aar_geometry::RobotModel Boom() {
  aar_geometry::RobotModelOptions urdf;
  urdf.package_paths = {kModels + "/../.."};
  return aar_geometry::LoadRobotModel(kModels + "/boom.urdf", urdf);
}

// Largest signed distance of `points` to the planes of `mesh`'s faces (negative: inside all).
double MaxPlaneDistance(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& points,
                        bool min_over_planes) {
  double worst = min_over_planes ? 1e9 : -1e9;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = mesh.TriangleNormal(static_cast<int>(t));
    const Eigen::Vector3d& v0 = mesh.vertices[mesh.triangles[t][0]];
    double far = -1e9;
    for (const auto& p : points) far = std::max(far, n.dot(p - v0));
    worst = min_over_planes ? std::min(worst, far) : std::max(worst, far);
  }
  return worst;
}

TEST(Inflate, EveryFacePlaneMovesOutByTheMargin) {
  const double margin = 0.1;
  const TriangleMesh shapes[] = {
      aar_geometry::WeldVertices(aar_geometry::MakeBox({1.2, 0.9, 0.6})).mesh,
      aar_geometry::WeldVertices(aar_geometry::MakeCylinder(0.3, 2.5)).mesh,
      aar_geometry::WeldVertices(aar_geometry::MakeSphere(0.11)).mesh};
  for (size_t s = 0; s < 3; ++s) {
    const TriangleMesh grown = Inflate(shapes[s], margin);
    EXPECT_TRUE(aar_geometry::IsConvex(grown, 1e-4)) << s;
    // The original's farthest vertex beyond each grown face plane: -margin for every plane
    // (exact where three planes meet, boxes and cylinders; the icosphere within 10 %).
    const double tol = s < 2 ? 1e-9 : 0.1 * margin;
    EXPECT_NEAR(MaxPlaneDistance(grown, shapes[s].vertices, false), -margin, tol) << s;
    EXPECT_NEAR(MaxPlaneDistance(grown, shapes[s].vertices, true), -margin, tol) << s;
  }
}

TEST(BoomParts, TheShippedBoomHasTwelveClosedConvexParts) {
  const BoomPartsOptions margins;
  const auto parts = LoadBoomParts(Boom(), margins);
  EXPECT_EQ(parts.size(), 12u);
  for (const auto& p : parts) {
    EXPECT_TRUE(p.adjacency.closed()) << p.name;
    EXPECT_TRUE(p.grown_adjacency.closed()) << p.name;
    // No spikes: a knife edge pushes its vertices out by margin / sin(half its angle); a box
    // corner moves sqrt(3) x margin, the blunt ruddevator's trailing edge corners 1.82 x.
    for (size_t v = 0; v < p.mesh.vertices.size(); ++v) {
      EXPECT_LE((p.grown.vertices[v] - p.mesh.vertices[v]).norm(), 2.0 * margins.cull_margin)
          << p.name << " vertex " << v;
      EXPECT_LE((p.outline.vertices[v] - p.mesh.vertices[v]).norm(),
                2.0 * margins.silhouette_margin)
          << p.name << " vertex " << v;
    }
  }
  BoomPartsOptions inverted;
  inverted.cull_margin = 0.01;  // the outline must lie inside the grown boom
  EXPECT_THROW(LoadBoomParts(Boom(), inverted), std::invalid_argument);
}

// The boom at a pose, seen from the default rig: centre (-20, 1, -3) m looking aft, 0.5 m
// baseline across the tanker's y axis (config/sim.yaml).
struct Scene {
  std::unique_ptr<BoomOcclusion> boom;
  std::map<std::string, Eigen::Isometry3d> links;
  Eigen::Vector3d eyes[2];
};

Scene MakeScene(const aar_description::BoomPose& pose) {
  const auto model = Boom();
  Scene s;
  s.boom = std::make_unique<BoomOcclusion>(LoadBoomParts(model));
  s.links = aar_geometry::ComputeLinkPoses(model, aar_description::BoomJointPositions(pose));
  s.eyes[0] = {-20.0, 0.75, -3.0};
  s.eyes[1] = {-20.0, 1.25, -3.0};
  EXPECT_TRUE(s.boom->Update(s.links, s.eyes[0], s.eyes[1]));
  return s;
}

TEST(BoomOcclusion, RebuildsOnlyWhenSomethingMoves) {
  Scene s = MakeScene(aar_description::DefaultBoomPose());
  EXPECT_FALSE(s.boom->Update(s.links, s.eyes[0], s.eyes[1]));
  auto moved = s.links;
  moved.at("telescope").translation().x() += 0.01;
  EXPECT_TRUE(s.boom->Update(moved, s.eyes[0], s.eyes[1]));
  EXPECT_TRUE(s.boom->Update(moved, s.eyes[0] + Eigen::Vector3d(0, 0, 0.01), s.eyes[1]));
  auto missing = s.links;
  missing.erase("telescope");
  try {
    s.boom->Update(missing, s.eyes[0], s.eyes[1]);
    ADD_FAILURE() << "no error for a missing link";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "no pose for boom link 'telescope'");
  }
}

int CheckRaysAndVolumesAgree(bool cull_behind_boom) {
  Scene s = MakeScene(aar_description::DefaultBoomPose());
  BoomOcclusionOptions options;
  options.cull_behind_boom = cull_behind_boom;
  s.boom = std::make_unique<BoomOcclusion>(LoadBoomParts(Boom()), options);
  EXPECT_TRUE(s.boom->Update(s.links, s.eyes[0], s.eyes[1]));
  // Points on the boom's visual surface, and points scattered around and behind it.
  const auto model = Boom();
  const TriangleMesh visual =
      aar_geometry::RobotMesh(model, s.links, aar_geometry::GeometryKind::kVisual);
  aar_geometry::SurfaceSamplingOptions sampling;
  sampling.num_points = 3000;
  sampling.seed = 3;
  std::vector<Eigen::Vector3d> points = aar_geometry::SampleSurface(visual, sampling).points;
  const size_t on_boom = points.size();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d centre = visual.Bounds().center();
  for (int i = 0; i < 20000; ++i)
    points.push_back(centre + Eigen::Vector3d(8 * u(rng), 4 * u(rng), 6 * u(rng)));

  const auto brute = s.boom->Cull(points, CullMethod::kRaysBrute);
  const auto bvh = s.boom->Cull(points, CullMethod::kRaysBvh);
  const auto volumes = s.boom->Cull(points, CullMethod::kVolumes);
  int differ_bvh = 0, differ_volumes = 0, culled = 0, on_boom_culled = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    differ_bvh += brute[i] != bvh[i];
    differ_volumes += brute[i] != volumes[i];
    culled += volumes[i];
    if (i < on_boom) on_boom_culled += volumes[i];
  }
  std::printf(
      "[ cull ] behind the boom %s: %d of %zu points culled (%d of %zu on the visual boom); BVH "
      "differs on %d, volumes on %d\n",
      cull_behind_boom ? "too" : "not", culled, points.size(), on_boom_culled, on_boom, differ_bvh,
      differ_volumes);
  // The visual boom lies inside the grown collision parts, bar a few samples of detail.
  EXPECT_GE(on_boom_culled, static_cast<int>(0.999 * on_boom));  // measured: 3000 of 3000
  EXPECT_GT(culled, static_cast<int>(on_boom) + 500);            // and the cones reach past it
  EXPECT_LT(culled, static_cast<int>(points.size()) / 2);
  // Float rays (Embree) and grazing rays could differ on a point; measured: 0 and 0.
  EXPECT_LE(differ_bvh, 1);
  EXPECT_LE(differ_volumes, 1);

  EXPECT_EQ(s.boom->Cull(points, CullMethod::kNone), std::vector<bool>(points.size(), false));
  return culled;
}

TEST(BoomOcclusion, RaysAndVolumesCullTheSamePoints) {
  const int behind = CheckRaysAndVolumesAgree(true);
  const int up_to_far_side = CheckRaysAndVolumesAgree(false);
  EXPECT_LT(up_to_far_side, behind - 200);  // the shadow beyond the boom is kept
}

// Block matching gives the pixels just off the boom's outline the boom's disparity (a 9 px block
// straddles the edge: about 5 cm at 15 m), and scatters every point along its ray by
// sigma_Z = Z^2 sigma_d / (f b): 0.3 px on the shipped rig (f b = 554 px m) is 0.12 m at 15 m, more
// than the 10 cm cull margin. Such points (here: samples of the collision parts grown by 5 cm, so
// off the boom but inside its 10 cm cull margin, at the boom's depth) are culled up to the grown
// boom's far side, which at the rim lies centimetres behind them: without a depth margin a share
// of them lands beyond it and stays in the cloud. Returns how many of 3000 stay for a
// cull_depth_coefficient; the ray methods must cull the same points as the volumes.
int FattenedBoomPointsKept(double cull_depth_coefficient) {
  Scene s = MakeScene(aar_description::DefaultBoomPose());
  BoomOcclusionOptions options;
  options.cull_depth_coefficient = cull_depth_coefficient;
  const std::vector<BoomPart> parts = LoadBoomParts(Boom());
  s.boom = std::make_unique<BoomOcclusion>(parts, options);
  EXPECT_TRUE(s.boom->Update(s.links, s.eyes[0], s.eyes[1]));
  TriangleMesh fattened;
  for (const BoomPart& part : parts)
    fattened.Append(Inflate(part.mesh, 0.05), s.links.at(part.link) * part.T_link_part);
  aar_geometry::SurfaceSamplingOptions sampling;
  sampling.num_points = 3000;
  sampling.seed = 5;
  std::vector<Eigen::Vector3d> points = aar_geometry::SampleSurface(fattened, sampling).points;
  std::mt19937 rng(9);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (auto& p : points) {
    const Eigen::Vector3d ray = p - s.eyes[0];
    p += 0.3 / 554.0 * ray.squaredNorm() * unit(rng) * ray.normalized();
  }
  const auto volumes = s.boom->Cull(points, CullMethod::kVolumes);
  const auto brute = s.boom->Cull(points, CullMethod::kRaysBrute);
  const auto bvh = s.boom->Cull(points, CullMethod::kRaysBvh);
  int kept = 0, differ = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    kept += !volumes[i];
    differ += (brute[i] != volumes[i]) + (bvh[i] != volumes[i]);
  }
  EXPECT_LE(differ, 2) << "rays and volumes, depth coefficient " << cull_depth_coefficient;
  return kept;
}

TEST(BoomOcclusion, ADepthMarginCullsTheBoomsScatteredPoints) {
  const int without = FattenedBoomPointsKept(0.0);
  const int with = FattenedBoomPointsKept(0.0009);  // half a pixel of disparity
  std::printf("[ cull ] fattened boom points kept (of 3000): %d without a depth margin, %d with\n",
              without, with);
  // Measured: 3 and 0 (with the margin off, 3 and 3: this fails). Few: where the camera looks
  // along the boom, its far side lies far behind a point at its rim.
  EXPECT_GE(without, 2);
  EXPECT_EQ(with, 0);
  EXPECT_THROW(BoomOcclusion(LoadBoomParts(Boom()), BoomOcclusionOptions{1e-6, false, -1.0}),
               std::invalid_argument);
}

TEST(DynamicReference, TheBoomHidesPartOfTheReceiverAtContact) {
  Scene s = MakeScene(aar_description::DefaultBoomPose());
  const TriangleMesh receiver = aar_geometry::LoadMesh(kModels + "/receiver.obj");
  aar_geometry::ReferenceModelOptions sampling;
  sampling.points_per_m2 = 150.0;
  DynamicReference reference(receiver, sampling);
  const Eigen::Isometry3d T_tanker_receiver =
      aar_geometry::MakeTransform({-35.0, 0.0, -10.19}, {0.0, -2.0 * M_PI / 180.0, 0.0});
  const auto without = reference.Build(T_tanker_receiver, s.eyes[0], s.eyes[1]);
  const auto with = reference.Build(T_tanker_receiver, *s.boom);
  EXPECT_TRUE(without.reshelled);
  EXPECT_FALSE(with.reshelled);  // same pose, reshell_distance 0: the eyes did not move
  ASSERT_EQ(with.cloud.size(), without.cloud.size());
  ASSERT_EQ(with.classes.size(), with.cloud.size());
  size_t counts[4] = {0, 0, 0, 0};
  for (const auto c : with.classes) ++counts[static_cast<int>(c)];
  std::printf(
      "[ dynamic ] %zu samples seen past the receiver itself: both %zu, left %zu, right "
      "%zu, neither %zu (without the boom: both %zu)\n",
      with.cloud.size(), counts[0], counts[1], counts[2], counts[3], without.both);
  EXPECT_EQ(counts[0], with.both);
  EXPECT_LT(with.both, without.both - 500);  // the boom hides a real part at contact
  EXPECT_GT(counts[1] + counts[2], 50u);     // and the cameras see round it differently
  EXPECT_GT(with.both, with.cloud.size() / 3);
  EXPECT_LT(with.cloud.size(), reference.size());  // the far side is self-occluded
}

}  // namespace
}  // namespace aar_occlusion
