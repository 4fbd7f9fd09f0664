#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/weld.h>

#include "aar_description/boom_model.h"
#include "aar_description/receiver_model.h"

namespace aar_description {
namespace {

using aar_geometry::TriangleMesh;
const std::string kModels = std::string(AAR_DESCRIPTION_SOURCE_DIR) + "/models";

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

aar_geometry::RobotModel LoadBoom() {
  aar_geometry::RobotModelOptions options;
  options.package_paths = {
      std::filesystem::path(AAR_DESCRIPTION_SOURCE_DIR).parent_path().string()};
  return aar_geometry::LoadRobotModel(kModels + "/boom.urdf", options);
}

// Signed volume by the divergence theorem: positive for a closed, outward-wound mesh.
double SignedVolume(const TriangleMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

TEST(ReceiverModel, PublishedDimensions) {
  const TriangleMesh receiver = MakeReceiverMesh();
  const Eigen::AlignedBox3d box = receiver.Bounds();
  EXPECT_NEAR(box.sizes().x(), 13.36, 0.10);  // length
  EXPECT_NEAR(box.sizes().y(), 16.61, 0.01);  // span
  EXPECT_NEAR(box.max().x(), 6.0, 1e-9);      // nose tip
  const Eigen::AlignedBox3d fuselage = aar_geometry::SelectParts(receiver, {"fuselage"}).Bounds();
  EXPECT_NEAR(fuselage.sizes().y(), 1.65, 0.02);
  const Eigen::AlignedBox3d tail =
      aar_geometry::SelectParts(receiver, {"horizontal_tail"}).Bounds();
  EXPECT_NEAR(tail.sizes().y(), 5.6, 0.01);
  const Eigen::AlignedBox3d nacelle =
      aar_geometry::SelectParts(receiver, {"left_nacelle"}).Bounds();
  EXPECT_NEAR(nacelle.center().y(), 2.6, 0.01);
  // The receptacle sits on the upper fuselage surface.
  const Eigen::Vector3d r = ReceptacleInReceiver();
  EXPECT_NEAR(r.z(), aar_geometry::SelectParts(receiver, {"fuselage"}).Bounds().max().z(), 0.05);
}

TEST(ReceiverModel, WellFormedAndOutward) {
  const TriangleMesh receiver = MakeReceiverMesh();
  const auto welded = aar_geometry::WeldVertices(receiver);
  const auto adjacency = aar_geometry::BuildAdjacency(welded.mesh);
  EXPECT_EQ(adjacency.nonmanifold_edges.size(), 0u);
  EXPECT_EQ(adjacency.inconsistent_edges.size(), 0u);
  for (const char* part : {"left_nacelle", "right_nacelle", "horizontal_tail"}) {
    const TriangleMesh p =
        aar_geometry::WeldVertices(aar_geometry::SelectParts(receiver, {part})).mesh;
    EXPECT_TRUE(aar_geometry::BuildAdjacency(p).closed()) << part;
    EXPECT_GT(SignedVolume(p), 0.0) << part;
  }
  // Nose and fuselage meet at the cabin ring: together they close the body.
  const TriangleMesh body =
      aar_geometry::WeldVertices(aar_geometry::SelectParts(receiver, {"nose", "fuselage"})).mesh;
  EXPECT_TRUE(aar_geometry::BuildAdjacency(body).closed());
  EXPECT_GT(SignedVolume(body), 0.0);
  EXPECT_EQ(
      aar_geometry::SelectParts(receiver, {"left_wing", "right_wing", "nose"}).part_names.size(),
      3u);
  ReceiverModelOptions with_props;
  with_props.propellers = true;
  EXPECT_GE(MakeReceiverMesh(with_props).FindPart("left_propeller"), 0);
  EXPECT_LT(receiver.FindPart("left_propeller"), 0);  // off by default
}

TEST(BoomModel, CollisionPartsAreClosedConvexAndAboutADozen) {
  const auto boom = LoadBoom();
  const auto poses = aar_geometry::ComputeLinkPoses(boom, BoomJointPositions(DefaultBoomPose()));
  const TriangleMesh collision =
      aar_geometry::RobotMesh(boom, poses, aar_geometry::GeometryKind::kCollision);
  EXPECT_EQ(collision.part_names.size(), 12u);
  for (const auto& part : collision.part_names) {
    const TriangleMesh p =
        aar_geometry::WeldVertices(aar_geometry::SelectParts(collision, {part})).mesh;
    EXPECT_TRUE(aar_geometry::BuildAdjacency(p).closed()) << part;
    // 0.1 mm: the OBJ file rounds the ruddevator hull to 6 decimals, tilting thin facets.
    EXPECT_TRUE(aar_geometry::IsConvex(p, 1e-4)) << part;
  }
  const auto* pitch = boom.FindJoint("boom_pitch");
  ASSERT_NE(pitch, nullptr);
  EXPECT_NEAR(aar_geometry::RadToDeg(pitch->lower), 20.0, 1e-4);
  EXPECT_NEAR(aar_geometry::RadToDeg(pitch->upper), 40.0, 1e-4);
  EXPECT_NEAR(aar_geometry::RadToDeg(boom.FindJoint("boom_roll")->upper), 15.0, 1e-4);
  EXPECT_NEAR(boom.FindJoint("boom_extension")->upper, 6.0, 1e-12);
  // Positive pitch lowers the boom: the nozzle is below the pivot.
  EXPECT_LT(poses.at("nozzle_tip").translation().z(),
            poses.at("boom_pivot").translation().z() - 5.0);
  // The visual meshes cover the collision parts' extent along the boom.
  const TriangleMesh visual =
      aar_geometry::RobotMesh(boom, poses, aar_geometry::GeometryKind::kVisual);
  EXPECT_NEAR(visual.Bounds().min().x(), collision.Bounds().min().x(), 0.05);
}

TEST(GeneratedFiles, CommittedFilesMatchTheGenerator) {
  const std::string tmp =
      std::filesystem::temp_directory_path().string() + "/aar_description_generated";
  std::filesystem::create_directories(tmp);
  const std::string command =
      std::string(AAR_DESCRIPTION_GENERATE_MODELS) + " " + tmp + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  for (const char* name : {"receiver.obj", "boom.urdf", "boom_visual.obj", "telescope_visual.obj",
                           "ruddevator_collision.obj"}) {
    EXPECT_EQ(ReadFile(tmp + "/" + name), ReadFile(kModels + "/" + name))
        << name << " is stale: run generate_models";
  }
  std::filesystem::remove_all(tmp);
}

}  // namespace
}  // namespace aar_description
