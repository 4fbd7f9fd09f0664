#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/pose.h>
#include <aar_geometry/pose_error.h>
#include <aar_geometry/robot_model.h>
#include <aar_geometry/weld.h>

#include "aar_description/boom_model.h"
#include "aar_description/boom_parts.h"
#include "aar_description/receiver_description.h"
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

TEST(UavModel, PublishedDimensions) {
  const TriangleMesh uav = MakeUavMesh();
  const Eigen::AlignedBox3d box = uav.Bounds();
  EXPECT_NEAR(box.sizes().y(), 39.9, 0.01);  // span
  EXPECT_NEAR(box.sizes().x(), 14.5, 0.01);  // length, nose tip to the V-tail's trailing edge
  EXPECT_NEAR(box.max().x(), 4.6, 1e-9);     // nose tip 4.6 m ahead of the datum
  EXPECT_NEAR(aar_geometry::SelectParts(uav, {"nose", "fuselage"}).Bounds().sizes().z(), 1.6, 0.05);
  const Eigen::AlignedBox3d tail = aar_geometry::SelectParts(uav, {"left_tail"}).Bounds();
  EXPECT_NEAR(tail.max().z() - 0.12, 3.0 * std::sin(aar_geometry::DegToRad(50.0)), 0.1);
  const Eigen::Vector3d r = UavReceptacleInReceiver();
  // The fuselage's top above the receptacle: the highest crossing of the vertical line through
  // it with the fuselage's triangles (barycentric test in the x-y plane).
  const TriangleMesh fuselage = aar_geometry::SelectParts(uav, {"fuselage"});
  double top = -1e9;
  for (const auto& t : fuselage.triangles) {
    const Eigen::Vector3d &a = fuselage.vertices[t[0]], &b = fuselage.vertices[t[1]],
                          &c = fuselage.vertices[t[2]];
    const Eigen::Vector2d e1 = (b - a).head<2>(), e2 = (c - a).head<2>(), p = (r - a).head<2>();
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    if (std::abs(det) < 1e-12) continue;
    const double u = (p.x() * e2.y() - p.y() * e2.x()) / det;
    const double v = (e1.x() * p.y() - e1.y() * p.x()) / det;
    if (u >= 0 && v >= 0 && u + v <= 1) top = std::max(top, (a + u * (b - a) + v * (c - a)).z());
  }
  EXPECT_NEAR(r.z(), top, 0.01);
  // The receptacle is on the upper fuselage ahead of the wing's leading edge.
  EXPECT_GT(r.x(), aar_geometry::SelectParts(uav, {"left_wing"}).Bounds().max().x());
}

TEST(UavModel, WellFormedClosedAndOutward) {
  const TriangleMesh uav = MakeUavMesh();
  const auto welded = aar_geometry::WeldVertices(uav);
  const auto adjacency = aar_geometry::BuildAdjacency(welded.mesh);
  EXPECT_EQ(adjacency.nonmanifold_edges.size(), 0u);
  EXPECT_EQ(adjacency.inconsistent_edges.size(), 0u);
  const TriangleMesh body =
      aar_geometry::WeldVertices(aar_geometry::SelectParts(uav, {"nose", "fuselage"})).mesh;
  EXPECT_TRUE(aar_geometry::BuildAdjacency(body).closed());
  EXPECT_GT(SignedVolume(body), 0.0);
  const TriangleMesh nacelle =
      aar_geometry::WeldVertices(aar_geometry::SelectParts(uav, {"engine_nacelle"})).mesh;
  EXPECT_TRUE(aar_geometry::BuildAdjacency(nacelle).closed());
  // Open only where wing and tail roots sit inside the fuselage.
  const auto check = aar_geometry::CheckReceiverMesh(uav, "uav");
  EXPECT_GT(check.open_edges, 0u);
  EXPECT_EQ(check.exposed_open_edges, 0u);
}

// The descriptions give each mesh in the receiver frame with its receptacle and contact pose.
TEST(ReceiverDescription, ShippedDescriptionsLoad) {
  const ReceiverDescription c12 = LoadReceiverDescription(kModels + "/c12.yaml");
  EXPECT_EQ(c12.name, "c12");
  EXPECT_EQ(c12.mesh, kModels + "/receiver.obj");
  EXPECT_TRUE(c12.has_receptacle);
  EXPECT_EQ(c12.receptacle, ReceptacleInReceiver());
  EXPECT_TRUE(c12.T_body_mesh.isApprox(Eigen::Isometry3d::Identity()));
  const TriangleMesh c12_mesh = LoadReceiverMesh(c12);
  EXPECT_EQ(c12_mesh.triangles.size(),
            aar_geometry::LoadMesh(kModels + "/receiver.obj").triangles.size());
  EXPECT_TRUE(
      c12.T_tanker_receiver_contact.translation().isApprox(Eigen::Vector3d(-35.0, 0, -10.19)));

  // Issue 16: the C-12's windscreen (glass triangles only on the nose) and its two propellers.
  ASSERT_EQ(c12.propellers.size(), 2u);
  EXPECT_LT((c12.propellers[0].hub - PropellerHubInReceiver(1.0)).norm(), 1e-9);  // 10 digits
  EXPECT_LT((c12.propellers[1].hub - PropellerHubInReceiver(-1.0)).norm(), 1e-9);
  EXPECT_EQ(c12.propellers[0].blades, 4);
  // The windscreen lies on the nose, on its upper side: triangles of the nose only reach into it.
  ASSERT_TRUE(c12.has_canopy);
  int in_canopy = 0;
  for (size_t t = 0; t < c12_mesh.triangles.size(); ++t) {
    const auto& tri = c12_mesh.triangles[t];
    const Eigen::Vector3d centre =
        (c12_mesh.vertices[tri[0]] + c12_mesh.vertices[tri[1]] + c12_mesh.vertices[tri[2]]) / 3.0;
    if (!c12.canopy.contains(centre) || c12_mesh.TriangleNormal(static_cast<int>(t)).z() <= 0.2)
      continue;
    ++in_canopy;
    EXPECT_EQ(c12_mesh.part_names[c12_mesh.triangle_parts[t]], "nose") << t;
  }
  EXPECT_GT(in_canopy, 10);

  const ReceiverDescription rq4 = LoadReceiverDescription(kModels + "/rq4.yaml");
  EXPECT_TRUE(rq4.propellers.empty());
  EXPECT_FALSE(rq4.has_canopy);
  EXPECT_EQ(rq4.static_parts, (std::vector<std::string>{"left_wing", "right_wing", "nose"}));
  EXPECT_EQ(rq4.receptacle, UavReceptacleInReceiver());
  // The station-axes file, mapped by the description, is the model built in the body frame.
  const TriangleMesh loaded = LoadReceiverMesh(rq4);
  const TriangleMesh built = MakeUavMesh();
  ASSERT_EQ(loaded.triangles.size(), built.triangles.size());
  EXPECT_LT((loaded.Bounds().min() - built.Bounds().min()).norm(), 1e-5);
  EXPECT_LT((loaded.Bounds().max() - built.Bounds().max()).norm(), 1e-5);
  EXPECT_EQ(loaded.part_names, built.part_names);
  // Contact: the receptacle on the nozzle tip at the trim attitude, within the 1 cm rounding.
  const auto boom = LoadBoom();
  const Eigen::Vector3d nozzle =
      aar_geometry::ComputeLinkPoses(boom, BoomJointPositions(DefaultBoomPose()))
          .at("nozzle_tip")
          .translation();
  for (const auto* d : {&c12, &rq4}) {
    EXPECT_LT((d->T_tanker_receiver_contact * d->receptacle - nozzle).norm(), 0.02) << d->name;
    const double range = d->T_tanker_receiver_contact.translation().norm();
    EXPECT_GE(range, 32.0) << d->name;  // region C
    EXPECT_LT(range, 38.0) << d->name;
  }
  // A bare mesh is its own description (body frame, metres, the C-12's part names), checked with
  // the default open-boundary allowance: the C-12's open ventral-fin root is refused then.
  const ReceiverDescription bare = LoadReceiverDescription(kModels + "/receiver.obj");
  EXPECT_FALSE(bare.has_receptacle);
  EXPECT_EQ(bare.static_parts, c12.static_parts);
  try {
    LoadReceiverMesh(bare);
    ADD_FAILURE() << "the C-12's open fin root passed";
  } catch (const aar_geometry::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("is open: 22 of 144 edges"), std::string::npos)
        << e.what();
  }
}

class BadReceiver : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("aar_bad_receiver_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  // The LoadError's message for loading the description and its mesh, or "".
  static std::string Refusal(const std::string& description) {
    try {
      LoadReceiverMesh(LoadReceiverDescription(description));
    } catch (const aar_geometry::LoadError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(BadReceiver, RefusedWithTheFileAndTheProblemNamed) {
  // A mesh in millimetres: 13 km long.
  aar_geometry::WriteObj((dir_ / "mm.obj").string(),
                         aar_geometry::Scaled(MakeReceiverMesh(), Eigen::Vector3d::Constant(1000)));
  const std::string mm = Refusal(Write("mm.yaml", "name: mm\nmesh: mm.obj\n"));
  EXPECT_NE(
      mm.find((dir_ / "mm.obj").string() + ": the receiver model is 16610 m across (x 13400 m"),
      std::string::npos)
      << mm;
  EXPECT_NE(mm.find("scale: 0.001"), std::string::npos) << mm;
  // ... which its description can scale.
  EXPECT_EQ(Refusal(Write("mm_scaled.yaml",
                          "name: mm\nmesh: mm.obj\nscale: 0.001\nmax_open_length: 2.0\n")),
            "");
  // Open: the nose taken away leaves the fuselage's front ring open.
  aar_geometry::WriteObj((dir_ / "open.obj").string(),
                         aar_geometry::SelectParts(MakeReceiverMesh(), {"fuselage", "left_wing"}));
  const std::string open = Refusal(Write("open.yaml", "name: open\nmesh: open.obj\n"));
  EXPECT_NE(open.find((dir_ / "open.obj").string() + ": the receiver model is open: "),
            std::string::npos)
      << open;
  // No faces: vertices only.
  const std::string none = Refusal(Write("none.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
  EXPECT_NE(none.find((dir_ / "none.obj").string() + ": "), std::string::npos) << none;
  EXPECT_NE(none.find("contains no faces"), std::string::npos) << none;  // assimp's words
  // Missing files: the description, and the mesh it names.
  EXPECT_NE(Refusal((dir_ / "absent.yaml").string()).find("absent.yaml: "), std::string::npos);
  const std::string missing = Refusal(Write("missing.yaml", "name: x\nmesh: nowhere.obj\n"));
  EXPECT_NE(missing.find((dir_ / "nowhere.obj").string() + ": "), std::string::npos) << missing;
  // Unknown and mistyped keys, a static part the mesh lacks.
  aar_geometry::WriteObj((dir_ / "c12.obj").string(), MakeReceiverMesh());
  const std::string unknown =
      Refusal(Write("unknown.yaml", "name: x\nmesh: c12.obj\nreceptacel: [0, 0, 1]\n"));
  EXPECT_NE(unknown.find("unknown.yaml: unknown key 'receptacel'"), std::string::npos) << unknown;
  const std::string nested =
      Refusal(Write("nested.yaml", "name: x\nmesh: c12.obj\nmesh_to_body: {rpy: [0, 0, 180]}\n"));
  EXPECT_NE(nested.find("unknown key 'mesh_to_body/rpy'"), std::string::npos) << nested;
  const std::string typed =
      Refusal(Write("typed.yaml", "name: x\nmesh: c12.obj\nreceptacle: [0, zero, 1]\n"));
  EXPECT_NE(typed.find("'receptacle' must be a finite number"), std::string::npos) << typed;
  const std::string part = Refusal(
      Write("part.yaml",
            "name: x\nmesh: c12.obj\nmax_open_length: 2\nstatic_parts: [left_wing, canard]\n"));
  EXPECT_NE(part.find("static part 'canard' is not a part of"), std::string::npos) << part;
  // Propellers and the canopy (issue 16): each key checked, inside the list too.
  const std::string head = "name: x\nmesh: c12.obj\nmax_open_length: 2\n";
  for (const auto& [text, expected] : std::vector<std::pair<std::string, std::string>>{
           {"propellers: [{hub: [3, 2, 0], blades: 2.5}]",
            "'propellers[0]/blades' must be a whole number from 1 to 16"},
           {"propellers: [{hub: [3, 2, 0]}, {hub: [3, -2, 0], rmp: 1700}]",
            "unknown key 'propellers[1]/rmp'"},
           {"propellers: [{radius: 1}]", "'propellers[0]/hub' must be a list of three numbers"},
           {"propellers: [{hub: [3, 2, 0], radius: 0.1, hub_radius: 0.2}]",
            "'propellers[0]': radius must be positive and above hub_radius"},
           {"propellers: [{hub: [3, 2, 0], axis: [0, 0, 0]}]",
            "'propellers[0]/axis' must not be zero"},
           {"propellers: {hub: [3, 2, 0]}", "'propellers' must be a list of maps"},
           {"canopy: {min: [4, -1, 0], max: [3, 1, 1]}", "'canopy': min must not exceed max"},
           {"canopy: {min: [4, -1, 0]}", "'canopy/max' must be a list of three numbers"}}) {
    const std::string refusal = Refusal(Write("props.yaml", head + text + "\n"));
    EXPECT_NE(refusal.find("props.yaml: " + expected), std::string::npos)
        << text << ": " << refusal;
  }
  EXPECT_EQ(Refusal(Write("props_ok.yaml", head + "propellers: [{hub: [3, 2, 0], blades: 3}]\n")),
            "");
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
  for (const char* name : {"receiver.obj", "c12.yaml", "rq4.obj", "rq4.yaml", "boom.urdf",
                           "boom_visual.obj", "telescope_visual.obj", "ruddevator_collision.obj"}) {
    EXPECT_EQ(ReadFile(tmp + "/" + name), ReadFile(kModels + "/" + name))
        << name << " is stale: run generate_models";
  }
  std::filesystem::remove_all(tmp);
}

TEST(BoomCollisionParts, TheShippedBoomHasTwelveClosedConvexPartsOnItsLinks) {
  const auto parts = LoadBoomCollisionParts(LoadBoom());
  EXPECT_EQ(parts.size(), 12u);
  for (const auto& p : parts) {
    EXPECT_TRUE(p.adjacency.closed()) << p.name;
    EXPECT_TRUE(aar_geometry::IsConvex(p.mesh, 1e-4)) << p.name;
    EXPECT_FALSE(p.link.empty()) << p.name;
  }
}

// A URDF whose links are given as XML, meshes next to it.
aar_geometry::RobotModel ModelFrom(const std::string& links) {
  const std::string xml = "<robot name=\"r\">" + links + "</robot>";
  return aar_geometry::ParseRobotModel(xml, "test", ::testing::TempDir());
}

void WriteObj(const std::string& name, const std::string& text) {
  std::ofstream(::testing::TempDir() + "/" + name) << text;
}

TEST(BoomCollisionParts, BadPartsAreRefusedNamingTheLink) {
  auto expect_error = [](const std::string& links, const std::string& needle) {
    try {
      LoadBoomCollisionParts(ModelFrom(links));
      ADD_FAILURE() << "no error for " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(
      "<link name=\"fairing\"><visual><geometry><box size=\"1 1 1\"/></geometry></visual></link>",
      "boom link 'fairing' has visual but no collision geometry");
  expect_error("<link name=\"empty\"/>", "no collision geometry");
  // An open box: the top face missing.
  WriteObj("open.obj",
           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "f 1 3 2\nf 1 4 3\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n"
           "f 4 1 5\nf 4 5 8\n");
  expect_error(
      "<link name=\"tube\"><collision><geometry><mesh filename=\"open.obj\"/></geometry>"
      "</collision></link>",
      "of boom link 'tube' is not closed (4 open");
  // A closed L-shaped prism: not convex.
  WriteObj("ell.obj",
           "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
           "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\n"
           "f 1 3 2\nf 1 4 3\nf 1 6 4\nf 4 6 5\n"
           "f 7 8 9\nf 7 9 10\nf 7 10 12\nf 10 11 12\n"
           "f 1 2 8\nf 1 8 7\nf 2 3 9\nf 2 9 8\nf 3 4 10\nf 3 10 9\n"
           "f 4 5 11\nf 4 11 10\nf 5 6 12\nf 5 12 11\nf 6 1 7\nf 6 7 12\n");
  expect_error(
      "<link name=\"bracket\"><collision><geometry><mesh filename=\"ell.obj\"/></geometry>"
      "</collision></link>",
      "of boom link 'bracket' is not convex");
}

}  // namespace
}  // namespace aar_description
