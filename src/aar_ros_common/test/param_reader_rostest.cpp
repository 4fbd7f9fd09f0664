#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <limits>

#include <ros/ros.h>

#include "aar_ros_common/param_reader.h"
#include "aar_ros_common/receiver_params.h"
#include "aar_ros_common/robot_description.h"

namespace aar_ros_common {
namespace {

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParamReader, ReadsDefaultsAndRefusesTheWrongType) {
  ros::NodeHandle pnh("~");
  ParamReader params(pnh);
  EXPECT_EQ(params.Get("rate", 1.0), 2.5);
  EXPECT_EQ(params.Get<std::string>("name", "right"), "left");
  EXPECT_EQ(params.Get("absent", 7), 7);
  EXPECT_EQ(params.Required("name", "a camera"), "left");
  const std::string wrong = ErrorOf([&] { params.Get("count", 3); });
  EXPECT_NE(wrong.find("/param_reader/count has the wrong type"), std::string::npos) << wrong;
  const std::string missing = ErrorOf([&] { params.Required("flight_path", "a CSV"); });
  EXPECT_NE(missing.find("required parameter /param_reader/flight_path (a CSV)"), std::string::npos)
      << missing;
  const std::string rule = ErrorOf([&] { params.Check(false, "rate", "must be positive"); });
  EXPECT_EQ(rule, "parameter /param_reader/rate must be positive");
}

// Timeouts: a negative or NaN one would wait forever or not at all; it is refused by name.
TEST(ParamReader, NonNegativeRefusesNegativeAndNan) {
  ros::NodeHandle nh("/timeouts");  // not under ~: the other tests read every key there
  nh.setParam("negative", -1.0);
  nh.setParam("nan", std::numeric_limits<double>::quiet_NaN());
  nh.setParam("fine", 0.5);
  ParamReader params(nh);
  EXPECT_EQ(params.GetNonNegative("fine", 1.0), 0.5);
  EXPECT_EQ(params.GetNonNegative("unset", 1.0), 1.0);
  const std::string negative = ErrorOf([&] { params.GetNonNegative("negative", 1.0); });
  EXPECT_NE(negative.find("/timeouts/negative must be a finite number >= 0, not -1"),
            std::string::npos)
      << negative;
  const std::string nan = ErrorOf([&] { params.GetNonNegative("nan", 1.0); });
  EXPECT_NE(nan.find("/timeouts/nan must be a finite number"), std::string::npos) << nan;
}

TEST(ParamReader, RejectsKeysNobodyRead) {
  ros::NodeHandle pnh("~");
  ParamReader params(pnh);
  params.Get("rate", 1.0);
  params.Get<std::string>("name", "");
  params.Get<std::string>("count", "");
  const std::string nested = ErrorOf([&] { params.RejectUnknown(); });
  EXPECT_NE(nested.find("unknown parameter /param_reader/dynamic/setting"), std::string::npos)
      << nested;
  params.AllowSubNamespaces();
  EXPECT_EQ(ErrorOf([&] { params.RejectUnknown(); }), "");

  ParamReader partial(pnh);
  partial.Get("rate", 1.0);
  partial.Allow("name");
  partial.AllowSubNamespaces();
  const std::string unknown = ErrorOf([&] { partial.RejectUnknown(); });
  EXPECT_EQ(unknown, "unknown parameter /param_reader/count (misspelt?)");
}

// Set keys override, unset ones keep the caller's defaults, and the default mesh is the shipped
// one (found through the package index, as both perception nodes find it).
TEST(ReceiverModel, ReadsOverTheCallersDefaults) {
  ros::NodeHandle nh("/receiver_model");
  ParamReader params(nh);
  aar_geometry::ReferenceModelOptions sampling;
  sampling.points_per_m2 = 127.0;
  sampling.seed = 4;
  const aar_description::ReceiverDescription receiver = LoadReceiverModel(params, sampling);
  EXPECT_EQ(sampling.points_per_m2, 50.0);
  EXPECT_EQ(sampling.seed, 4u);
  EXPECT_EQ(sampling.visibility_tolerance, 0.02);
  EXPECT_TRUE(std::filesystem::exists(receiver.mesh)) << receiver.mesh;
  EXPECT_EQ(receiver.name, "c12");
  EXPECT_NE(receiver.path.find("aar_description/models/c12.yaml"), std::string::npos)
      << receiver.path;
  EXPECT_EQ(ErrorOf([&] { params.RejectUnknown(); }), "");
}

// The boom's URDF is found from the root namespace (occlusion and registration run there), by
// searching up from a namespace below it (stereo's), with package:// meshes found by rospack; a
// parameter that is nowhere is named.
TEST(RobotDescription, FoundFromTheRootAndFromBelowItNamedWhenMissing) {
  for (const std::string ns : {"/", "/stereo", "/stereo/aar_stereo"}) {
    try {
      const aar_geometry::RobotModel boom =
          LoadRobotDescription(ros::NodeHandle(ns), "robot_description");
      ASSERT_FALSE(boom.links.empty()) << ns;
      size_t meshes = 0;
      for (const auto& link : boom.links) {
        for (const auto& v : link.visuals) {
          if (v.source.find("aar_description/models/") == std::string::npos) continue;
          EXPECT_TRUE(std::filesystem::exists(v.source)) << v.source;
          meshes += !v.mesh.vertices.empty();
        }
      }
      EXPECT_GT(meshes, 0u) << ns << ": no package:// mesh loaded";
    } catch (const std::exception& e) {
      ADD_FAILURE() << ns << ": " << e.what();
    }
  }
  try {
    LoadRobotDescription(ros::NodeHandle("/nowhere"), "no_such_urdf");
    ADD_FAILURE() << "a missing URDF parameter was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nowhere/no_such_urdf"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aar_ros_common

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "param_reader");
  return RUN_ALL_TESTS();
}
