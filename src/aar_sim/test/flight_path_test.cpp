#include "aar_sim/flight_path.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <aar_geometry/load_error.h>
#include <aar_geometry/robot_model.h>
#include <ros/package.h>

namespace aar_sim {
namespace {

using aar_geometry::DegToRad;

class TempDir {
 public:
  TempDir() {
    std::string pattern = std::filesystem::temp_directory_path().string() + "/aar_sim_test_XXXXXX";
    path_ = ::mkdtemp(pattern.data());
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ + "/" + name) << text;
    return path_ + "/" + name;
  }
  std::string Path(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

TEST(FlightPath, LoadsAndInterpolates) {
  TempDir dir;
  const FlightPath path = FlightPath::Load(dir.Write("p.csv",
                                                     "# comment line\n"
                                                     "t, x, y, z, roll, pitch, yaw\n"
                                                     "0, -100, 0, -20, 0, 0, 0\n"
                                                     "\n"
                                                     "2, -98, 1, -21, 10, 0, 20\n"));
  ASSERT_EQ(path.rows().size(), 2u);
  EXPECT_FALSE(path.has_boom());
  const FlightPathRow mid = path.At(1.0);
  EXPECT_TRUE(mid.position_m.isApprox(Eigen::Vector3d(-99.0, 0.5, -20.5)));
  // Slerp halfway between identity and (roll 10, yaw 20) is the half rotation of their relative
  // rotation.
  const Eigen::Quaterniond q_end(
      aar_geometry::RotationFromRollPitchYaw({DegToRad(10), 0, DegToRad(20)}));
  const Eigen::Quaterniond q_mid(aar_geometry::RotationFromRollPitchYaw(mid.rpy));
  EXPECT_NEAR(q_mid.angularDistance(Eigen::Quaterniond::Identity()),
              0.5 * q_end.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
  EXPECT_NEAR(q_mid.angularDistance(q_end),
              0.5 * q_end.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
  // Clamped outside the path.
  EXPECT_TRUE(path.At(-5.0).position_m.isApprox(path.rows().front().position_m));
  EXPECT_TRUE(path.At(99.0).position_m.isApprox(path.rows().back().position_m));
  EXPECT_TRUE(path.At(std::nan("")).position_m.isApprox(path.rows().front().position_m));
}

TEST(FlightPath, BoomColumnsInAnyOrder) {
  TempDir dir;
  const FlightPath path =
      FlightPath::Load(dir.Write("boom.csv",
                                 "boom_extension,t,x,y,z,roll,pitch,yaw,boom_pitch,boom_roll\n"
                                 "1.0,0,-40,0,-10,0,-2,0,30,0\n"
                                 "3.0,1,-39,0,-10,0,-2,0,34,-4\n"));
  ASSERT_TRUE(path.has_boom());
  const FlightPathRow mid = path.At(0.5);
  ASSERT_TRUE(mid.boom.has_value());
  EXPECT_NEAR(mid.boom->extension, 2.0, 1e-12);
  EXPECT_NEAR(mid.boom->pitch, DegToRad(32.0), 1e-12);
  EXPECT_NEAR(mid.boom->roll, DegToRad(-2.0), 1e-12);
  EXPECT_NEAR(mid.rpy.pitch, DegToRad(-2.0), 1e-12);
}

TEST(FlightPath, WriteThenLoadRoundTrips) {
  TempDir dir;
  std::vector<FlightPathRow> rows(3);
  for (int i = 0; i < 3; ++i) {
    rows[i].t = 0.1 * i;
    rows[i].position_m = Eigen::Vector3d(-50.0 + i, 0.25 * i, -12.0);
    rows[i].rpy = {DegToRad(1.0 * i), DegToRad(-2.0), DegToRad(0.5)};
    rows[i].boom = BoomPose{DegToRad(30.0), DegToRad(-1.0 * i), 1.5};
  }
  WriteFlightPath(dir.Path("out.csv"), rows);
  const FlightPath back = FlightPath::Load(dir.Path("out.csv"));
  ASSERT_EQ(back.rows().size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(back.rows()[i].t, rows[i].t, 1e-9);
    EXPECT_TRUE(back.rows()[i].position_m.isApprox(rows[i].position_m, 1e-6));
    EXPECT_NEAR(back.rows()[i].rpy.roll, rows[i].rpy.roll, 1e-6);
    EXPECT_NEAR(back.rows()[i].boom->roll, rows[i].boom->roll, 1e-6);
  }
}

// Bad files: LoadError naming the file, the line and the problem.
void ExpectError(const std::string& path, const std::string& fragment) {
  try {
    FlightPath::Load(path);
    ADD_FAILURE() << "loaded " << path;
  } catch (const aar_geometry::LoadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(FlightPathErrors, NameFileLineAndProblem) {
  TempDir dir;
  const std::string header = "t,x,y,z,roll,pitch,yaw\n";
  ExpectError(dir.Path("absent.csv"), "No such file");
  ExpectError(dir.Write("empty.csv", ""), "empty");
  ExpectError(dir.Write("blank.csv", "\n# only a comment\n"), "no header");
  ExpectError(dir.Write("header_only.csv", header), "no data rows");
  ExpectError(dir.Write("missing.csv", "t,x,y,z,roll,pitch\n0,1,2,3,4,5\n"),
              "line 1: missing column 'yaw'");
  ExpectError(dir.Write("twice.csv", "t,x,y,z,roll,pitch,yaw,x\n"),
              "line 1: column 'x' appears twice");
  ExpectError(dir.Write("nan.csv", header + "0,1,2,3,4,5,6\n1,-40,abc,3,4,5,6\n"),
              "line 3: column 'y': 'abc' is not a finite number");
  ExpectError(dir.Write("inf.csv", header + "0,inf,2,3,4,5,6\n"), "line 2: column 'x': 'inf'");
  ExpectError(dir.Write("blank_cell.csv", header + "0,1,,3,4,5,6\n"), "line 2: column 'y': ''");
  ExpectError(dir.Write("short.csv", header + "0,1,2,3,4,5\n"), "line 2: 6 cells, header has 7");
  ExpectError(dir.Write("back.csv", header + "0,1,2,3,4,5,6\n1,1,2,3,4,5,6\n1,1,2,3,4,5,6\n"),
              "line 4: time 1 s does not increase");
  ExpectError(dir.Write("half_boom.csv", "t,x,y,z,roll,pitch,yaw,boom_pitch\n0,1,2,3,4,5,6,30\n"),
              "boom columns must be all");
}

// The shipped boom's joints, as the sim loads them.
std::vector<aar_geometry::Joint> BoomJoints() {
  const std::string description = ros::package::getPath("aar_description");
  aar_geometry::RobotModelOptions options;
  options.package_paths = {std::filesystem::path(description).parent_path().string()};
  return aar_geometry::LoadRobotModel(description + "/models/boom.urdf", options).joints;
}

// Boom cells outside the URDF's limits (pitch 20 to 40 deg, roll -15 to 15 deg, extension 0 to
// 6 m): LoadError naming the file, line, column and the limits.
TEST(FlightPathErrors, BoomOutsideTheJointLimits) {
  TempDir dir;
  const FlightPathOptions boom{BoomJoints()};
  const std::string header = "t,x,y,z,roll,pitch,yaw,boom_pitch,boom_roll,boom_extension\n";
  const std::string good = "0,-40,0,-10,0,0,0,30,0,1\n";
  auto expect_error = [&](const std::string& name, const std::string& row,
                          const std::string& fragment) {
    const std::string path = dir.Write(name, header + good + row);
    try {
      FlightPath::Load(path, boom);
      ADD_FAILURE() << "loaded " << path;
    } catch (const aar_geometry::LoadError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error("pitch.csv", "1,-39,0,-10,0,0,0,170,0,1\n",
               "line 3: column 8 'boom_pitch': 170 deg is outside the limits of joint "
               "'boom_pitch', 20 to 40 deg");
  expect_error("roll.csv", "1,-39,0,-10,0,0,0,30,95,1\n",
               "line 3: column 9 'boom_roll': 95 deg is outside the limits of joint 'boom_roll', "
               "-15 to 15 deg");
  expect_error("extension.csv", "1,-39,0,-10,0,0,0,30,0,-50\n",
               "line 3: column 10 'boom_extension': -50 m is outside the limits of joint "
               "'boom_extension', 0 to 6 m");
  expect_error("low_pitch.csv", "1,-39,0,-10,0,0,0,19.9,0,1\n", "19.9 deg is outside");

  // The limits themselves load (the URDF's are rounded to six digits: 20 deg is 0.349066).
  const std::string edges = dir.Write("edges.csv", header +
                                                       "0,-40,0,-10,0,0,0,20,-15,0\n"
                                                       "1,-39,0,-10,0,0,0,40,15,6\n");
  EXPECT_EQ(FlightPath::Load(edges, boom).rows().size(), 2u);
  // Without a boom model nothing is checked (no model to check against).
  EXPECT_EQ(FlightPath::Load(dir.Path("pitch.csv")).rows().size(), 2u);

  // A boom model without the column's joint is named.
  std::vector<aar_geometry::Joint> no_roll = BoomJoints();
  no_roll.erase(std::remove_if(no_roll.begin(), no_roll.end(),
                               [](const auto& j) { return j.name == "boom_roll"; }),
                no_roll.end());
  try {
    FlightPath::Load(edges, {no_roll});
    ADD_FAILURE() << "loaded " << edges << " against a boom without boom_roll";
  } catch (const aar_geometry::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("line 1: column 'boom_roll': the boom model has no joint "
                                         "'boom_roll'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace aar_sim
