#include "aar_geometry/robot_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "aar_geometry/adjacency.h"
#include "aar_geometry/load_error.h"
#include "aar_geometry/weld.h"
#include "test_files.h"

namespace aar_geometry {
namespace {

// The folder that holds the aar_geometry package, for package:// look-ups.
std::string PackageRoot() {
  return std::filesystem::path(test::DataPath(""))
      .parent_path()
      .parent_path()
      .parent_path()
      .parent_path();
}

RobotModel LoadFixture() {
  RobotModelOptions options;
  options.package_paths = {PackageRoot()};
  return LoadRobotModel(test::DataPath("boom_primitives.urdf"), options);
}

TEST(RobotModel, LinksJointsAndLimits) {
  const RobotModel model = LoadFixture();
  EXPECT_EQ(model.name, "boom_primitives");
  EXPECT_EQ(model.root_link, "tanker");
  EXPECT_EQ(model.links.size(), 4u);
  EXPECT_EQ(model.joints.size(), 3u);
  const Joint* pitch = model.FindJoint("boom_pitch");
  ASSERT_NE(pitch, nullptr);
  EXPECT_EQ(pitch->type, JointType::kRevolute);
  EXPECT_EQ(pitch->parent_link, "tanker");
  EXPECT_EQ(pitch->child_link, "boom_tube");
  EXPECT_NEAR(pitch->lower, 0.349, 1e-12);
  EXPECT_NEAR(pitch->upper, 0.698, 1e-12);
  EXPECT_TRUE(pitch->axis.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_EQ(model.FindJoint("telescope")->type, JointType::kPrismatic);
  EXPECT_EQ(model.FindJoint("nozzle_mount")->type, JointType::kFixed);
  EXPECT_FALSE(model.FindJoint("nozzle_mount")->movable());
  EXPECT_EQ(model.FindLink("nowhere"), nullptr);
}

TEST(RobotModel, JointLimitsAreChecked) {
  const RobotModel model = LoadFixture();
  const Joint* pitch = model.FindJoint("boom_pitch");
  EXPECT_TRUE(pitch->WithinLimits(0.5));
  EXPECT_TRUE(pitch->WithinLimits(0.349 - 0.5 * kJointLimitTolerance));  // a rounded limit
  EXPECT_FALSE(pitch->WithinLimits(0.349 - 2.0 * kJointLimitTolerance));
  EXPECT_FALSE(pitch->WithinLimits(100.0));
  EXPECT_FALSE(pitch->WithinLimits(std::nan("")));
  EXPECT_TRUE(model.FindJoint("nozzle_mount")->WithinLimits(5.0));  // fixed: no limits
  EXPECT_NO_THROW(CheckJointLimits(model, {{"boom_pitch", 0.698}, {"telescope", 0.0}}));
  auto expect_refused = [&](const std::string& joint, double value, const std::string& text) {
    try {
      CheckJointLimits(model, {{joint, value}});
      ADD_FAILURE() << joint << " = " << value << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  expect_refused("boom_pitch", 100.0,
                 "joint 'boom_pitch' position 100 rad is outside its limits 0.349 to 0.698 rad");
  expect_refused("telescope", -50.0,
                 "joint 'telescope' position -50 m is outside its limits 0 to 6 m");
}

TEST(RobotModel, PrimitivesBecomeClosedMeshes) {
  const RobotModel model = LoadFixture();
  const Link* tube = model.FindLink("boom_tube");
  ASSERT_NE(tube, nullptr);
  ASSERT_EQ(tube->collisions.size(), 2u);
  EXPECT_EQ(tube->collisions[0].name, "tube");
  EXPECT_EQ(tube->collisions[0].source, "cylinder");
  EXPECT_EQ(tube->collisions[0].mesh.triangles.size(), 4u * 32u);
  EXPECT_EQ(tube->collisions[1].source, "box");
  EXPECT_EQ(tube->collisions[1].mesh.triangles.size(), 12u);
  EXPECT_EQ(tube->visuals[0].name, "boom_tube/visual0");  // unnamed elements get a name
  EXPECT_EQ(model.FindLink("nozzle")->collisions[0].source, "sphere");
  for (const auto& link : model.links) {
    for (const auto& element : link.collisions) {
      EXPECT_TRUE(BuildAdjacency(element.mesh).closed()) << element.name;
    }
  }
}

TEST(RobotModel, MeshesResolvedAndScaled) {
  const RobotModel model = LoadFixture();
  const Link* nozzle = model.FindLink("nozzle");
  ASSERT_EQ(nozzle->visuals.size(), 2u);
  // Relative to the URDF's folder, scale 0.5 of a 1 m cube.
  EXPECT_EQ(std::filesystem::path(nozzle->visuals[0].source).filename(), "cube.stl");
  EXPECT_TRUE(nozzle->visuals[0].mesh.Bounds().max().isApprox(Eigen::Vector3d::Constant(0.25)));
  // package://aar_geometry/..., scale 0.2.
  EXPECT_TRUE(nozzle->visuals[1].mesh.Bounds().max().isApprox(Eigen::Vector3d::Constant(0.1)));
  EXPECT_EQ(nozzle->visuals[1].mesh.part_names, std::vector<std::string>{"nozzle_package"});
}

TEST(RobotModel, ForwardKinematicsMatchesHandComputation) {
  const RobotModel model = LoadFixture();
  const double pitch = 0.5, extension = 2.0;
  const auto poses = ComputeLinkPoses(model, {{"boom_pitch", pitch}, {"telescope", extension}});
  ASSERT_EQ(poses.size(), 4u);
  // Nozzle origin: pivot (-10, 0, -1) plus, rotated by `pitch` about y, 8 + extension + 2 m aft.
  const double a = -(8.0 + extension + 2.0);
  const Eigen::Vector3d expected(-10.0 + a * std::cos(pitch), 0.0, -1.0 - a * std::sin(pitch));
  EXPECT_TRUE(poses.at("nozzle").translation().isApprox(expected, 1e-12))
      << poses.at("nozzle").translation().transpose();
  EXPECT_TRUE(poses.at("nozzle").linear().isApprox(
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix()));
  // Joints left out stay at zero.
  const auto rest = ComputeLinkPoses(model);
  EXPECT_TRUE(rest.at("nozzle").translation().isApprox(Eigen::Vector3d(-20.0, 0.0, -1.0)));
}

TEST(RobotModel, CollisionMeshHasOnePartPerElementInRootFrame) {
  const RobotModel model = LoadFixture();
  const auto poses = ComputeLinkPoses(model, {{"boom_pitch", 0.0}});
  const TriangleMesh collision = RobotMesh(model, poses, GeometryKind::kCollision);
  EXPECT_EQ(collision.part_names.size(), 4u);
  for (const char* part : {"tube", "ruddevator", "inner", "tip"}) {
    ASSERT_GE(collision.FindPart(part), 0) << part;
    EXPECT_TRUE(BuildAdjacency(WeldVertices(SelectParts(collision, {part})).mesh).closed()) << part;
  }
  // Tube: 8 m cylinder along the boom from the pivot at x = -10 aft to x = -18.
  const Eigen::AlignedBox3d tube = SelectParts(collision, {"tube"}).Bounds();
  EXPECT_NEAR(tube.max().x(), -10.0, 1e-9);
  EXPECT_NEAR(tube.min().x(), -18.0, 1e-9);
  EXPECT_NEAR(tube.max().z(), -0.75, 1e-9);
}

TEST(RobotModel, RejectsUnknownJointsAndBadValues) {
  const RobotModel model = LoadFixture();
  EXPECT_THROW(ComputeLinkPoses(model, {{"boom_yaw", 0.1}}), std::invalid_argument);
  EXPECT_THROW(ComputeLinkPoses(model, {{"nozzle_mount", 0.1}}), std::invalid_argument);
  EXPECT_THROW(ComputeLinkPoses(model, {{"telescope", std::nan("")}}), std::invalid_argument);
}

void ExpectLoadError(const std::string& path, const std::string& fragment) {
  test::ExpectLoadError([](const std::string& p) { LoadRobotModel(p); }, path, fragment);
}

TEST(RobotModel, ParsesTextWithMeshesRelativeToBaseDir) {
  const std::string xml = R"(<robot name="r"><link name="a">
    <visual><geometry><mesh filename="cube.stl" scale="2 2 2"/></geometry></visual></link></robot>)";
  const RobotModel model = ParseRobotModel(xml, "robot_description", test::DataPath(""));
  EXPECT_TRUE(
      model.FindLink("a")->visuals[0].mesh.Bounds().max().isApprox(Eigen::Vector3d::Ones()));
  test::ExpectLoadError([](const std::string& source) { ParseRobotModel("", source, "."); },
                        "robot_description", "empty");
  test::ExpectLoadError([](const std::string& source) { ParseRobotModel("<robot/>", source, "."); },
                        "robot_description", "not a valid URDF");
}

TEST(RobotModel, PackagesAreFoundByTheirNameNotTheirFolder) {
  // A copy of the package in a folder of another name, reached through a root with a trailing /.
  test::TempDir dir;
  std::filesystem::create_directories(dir.Path("ws/renamed_folder/test/data"));
  std::filesystem::copy_file(test::DataPath("cube.stl"),
                             dir.Path("ws/renamed_folder/test/data/cube.stl"));
  dir.Write("ws/renamed_folder/package.xml",
            "<package format=\"3\"><name>aar_geometry</name></package>");
  RobotModelOptions options;
  options.package_paths = {dir.Path("ws/")};
  const RobotModel model = LoadRobotModel(test::DataPath("boom_primitives.urdf"), options);
  EXPECT_EQ(model.FindLink("nozzle")->visuals[1].source,
            dir.Path("ws/renamed_folder/test/data/cube.stl"));
}

TEST(RobotModel, SameElementNameOnTwoLinksStaysTwoParts) {
  test::TempDir dir;
  const RobotModel model = LoadRobotModel(dir.Write("twins.urdf", R"(<robot name="r">
    <link name="a"><collision name="part"><geometry><box size="1 1 1"/></geometry></collision></link>
    <joint name="j" type="fixed"><parent link="a"/><child link="b"/><origin xyz="3 0 0"/></joint>
    <link name="b"><collision name="part"><geometry><box size="1 1 1"/></geometry></collision></link>
  </robot>)"));
  const TriangleMesh mesh = RobotMesh(model, ComputeLinkPoses(model), GeometryKind::kCollision);
  EXPECT_EQ(mesh.part_names.size(), 2u);
  EXPECT_EQ(SelectParts(mesh, {mesh.part_names[0]}).triangles.size(), 12u);
}

TEST(RobotModel, NegativeMeshScaleKeepsNormalsOutward) {
  test::TempDir dir;
  const std::string urdf = dir.Write("mirror.urdf", R"(<robot name="r"><link name="a">
    <visual><geometry><mesh filename=")" + test::DataPath("cube.stl") +
                                                        R"(" scale="1 -1 1"/></geometry></visual>
  </link></robot>)");
  const TriangleMesh m = LoadRobotModel(urdf).FindLink("a")->visuals[0].mesh;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const Eigen::Vector3d c = (m.vertices[tri[0]] + m.vertices[tri[1]] + m.vertices[tri[2]]) / 3.0;
    EXPECT_GT(m.TriangleNormal(static_cast<int>(t)).dot(c), 0.0);
  }
}

TEST(RobotModelErrors, MissingEmptyAndNotXml) {
  test::TempDir dir;
  ExpectLoadError(dir.Path("absent.urdf"), "No such file");
  ExpectLoadError(dir.Write("empty.urdf", ""), "empty");
  ExpectLoadError(dir.Write("text.urdf", "just some words"), "not a valid URDF");
  ExpectLoadError(dir.Write("cut.urdf", "<robot name=\"r\"><link name=\"a\"><visual>"),
                  "not a valid URDF");
}

TEST(RobotModelErrors, XmlThatIsNotAValidRobot) {
  test::TempDir dir;
  ExpectLoadError(dir.Write("no_robot.urdf", "<?xml version=\"1.0\"?><launch/>"), "robot");
  // A joint whose child link does not exist: urdfdom's reason is passed on.
  ExpectLoadError(dir.Write("dangling.urdf", R"(<robot name="r">
    <link name="a"/>
    <joint name="j" type="fixed"><parent link="a"/><child link="ghost"/></joint>
  </robot>)"),
                  "ghost");
  ExpectLoadError(dir.Write("bad_cylinder.urdf", R"(<robot name="r"><link name="a">
    <collision><geometry><cylinder radius="0.1"/></geometry></collision></link></robot>)"),
                  "length");
  // Joints in a cycle apart from the root: urdfdom takes it (the urdf fuzz target found it), and
  // no pose could place b and c.
  ExpectLoadError(dir.Write("cycle.urdf", R"(<robot name="r">
    <link name="root"/><link name="a"/><link name="b"/><link name="c"/>
    <joint name="j0" type="fixed"><parent link="root"/><child link="a"/></joint>
    <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
    <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint>
  </robot>)"),
                  "link 'b' is not connected to the root link 'root' (its joints form a cycle)");
}

TEST(RobotModelErrors, MissingMeshNamesLinkAndMesh) {
  test::TempDir dir;
  const std::string path = dir.Write("missing_mesh.urdf", R"(<robot name="r"><link name="boom">
    <collision name="fairing"><geometry><mesh filename="meshes/fairing.stl"/></geometry></collision>
  </link></robot>)");
  ExpectLoadError(path, "link 'boom' collision 0 ('fairing')");
  ExpectLoadError(path, dir.Path("meshes/fairing.stl"));
  ExpectLoadError(dir.Write("unknown_package.urdf", R"(<robot name="r"><link name="boom">
    <visual><geometry><mesh filename="package://no_such_pkg/m.stl"/></geometry></visual>
  </link></robot>)"),
                  "package 'no_such_pkg'");
}

TEST(RobotModelErrors, BrokenMeshNamesLink) {
  test::TempDir dir;
  dir.Write("broken.stl", "solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0\n");
  ExpectLoadError(dir.Write("broken_mesh.urdf", R"(<robot name="r"><link name="nozzle">
    <visual><geometry><mesh filename="broken.stl"/></geometry></visual>
  </link></robot>)"),
                  "link 'nozzle' visual 0");
}

}  // namespace
}  // namespace aar_geometry
