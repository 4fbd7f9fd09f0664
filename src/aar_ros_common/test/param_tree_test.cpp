// ParamReader over a parameter tree (no master): what the parameter fuzz target reads through,
// with the same conversions as over the server.
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <functional>

#include "aar_ros_common/param_reader.h"

namespace aar_ros_common {
namespace {

using XmlRpc::XmlRpcValue;

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// /stereo/aar_stereo/{...} and /sim/stamp_offset, as rosparam would store them.
XmlRpcValue Tree() {
  XmlRpcValue tree;
  XmlRpcValue& node = tree["stereo"]["aar_stereo"];
  node["rate"] = 2.5;
  node["count"] = 3;
  node["whole"] = 4.0;
  node["half"] = 2.5;
  node["huge"] = 1e10;
  node["nan"] = std::nan("");
  node["flag"] = true;
  node["name"] = std::string("left");
  node["dynamic"]["setting"] = 1;
  tree["sim"]["stamp_offset"] = 5;
  return tree;
}

TEST(ParamTree, ReadsWithTheServersConversions) {
  ParamReader params(Tree(), "/stereo/aar_stereo");
  EXPECT_EQ(params.Get("rate", 1.0), 2.5);
  EXPECT_EQ(params.Get("count", 1.0), 3.0);  // an int is a double too
  EXPECT_EQ(params.Get("count", 0), 3);
  EXPECT_EQ(params.Get("flag", false), true);
  EXPECT_EQ(params.Get<std::string>("name", ""), "left");
  EXPECT_EQ(params.Get("absent", 7), 7);
  EXPECT_EQ(params.Get("/sim/stamp_offset", 1.0), 5.0);  // absolute names from the root
  EXPECT_EQ(params.Get("dynamic/setting", 0), 1);        // and below ~
  EXPECT_EQ(params.Resolve("rate"), "/stereo/aar_stereo/rate");
  const std::string wrong = ErrorOf([&] { params.Get("name", 3); });
  EXPECT_EQ(wrong,
            "parameter /stereo/aar_stereo/name has the wrong type (an int expected, not a string)");
  EXPECT_NE(ErrorOf([&] { params.Get("flag", 1.0); }).find("(a number expected, not a bool)"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { params.Get<std::string>("count", ""); }).find("a string expected"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { params.Get("dynamic", 0); }).find("not a map"), std::string::npos);
}

// roscpp's getParam(int&) rounds any double and converts one beyond int's range with undefined
// behaviour (measured on a master here: 2.5 gave 3, -2.3 gave -3, 1e10 gave -2147483648, each
// reported as read): only whole numbers in range are taken.
TEST(ParamTree, AnIntTakesOnlyAWholeDoubleInRange) {
  ParamReader params(Tree(), "/stereo/aar_stereo");
  EXPECT_EQ(params.Get("whole", 0), 4);
  EXPECT_EQ(ErrorOf([&] { params.Get("half", 0); }),
            "parameter /stereo/aar_stereo/half must be a whole number from -2147483648 to "
            "2147483647, not 2.5");
  EXPECT_NE(ErrorOf([&] { params.Get("huge", 0); }).find("not 1e+10"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { params.Get("nan", 0); }).find("not nan"), std::string::npos);
}

// YAML's .nan and .inf are numbers to rosparam, but no setting means either: the params fuzz
// target found the simulator taking camera_x .nan and stamp_offset .inf.
TEST(ParamTree, ADoubleMustBeFinite) {
  XmlRpcValue tree;
  tree["sim"]["camera_x"] = std::nan("");
  tree["sim"]["stamp_offset"] = HUGE_VAL;
  ParamReader params(tree, "/sim");
  EXPECT_EQ(ErrorOf([&] { params.Get("camera_x", -20.0); }),
            "parameter /sim/camera_x must be a finite number, not nan");
  EXPECT_EQ(ErrorOf([&] { params.Get("stamp_offset", 1.0); }),
            "parameter /sim/stamp_offset must be a finite number, not inf");
}

TEST(ParamTree, RejectsKeysNobodyReadAsOverTheServer) {
  ParamReader params(Tree(), "/stereo/aar_stereo");
  for (const char* key : {"rate", "count", "whole", "half", "huge", "nan", "flag"})
    params.Allow(key);
  EXPECT_EQ(ErrorOf([&] { params.RejectUnknown(); }),
            "unknown parameter /stereo/aar_stereo/dynamic/setting (misspelt?)");
  params.AllowSubNamespaces();
  EXPECT_EQ(ErrorOf([&] { params.RejectUnknown(); }),
            "unknown parameter /stereo/aar_stereo/name (misspelt?)");
  params.Allow("name");
  EXPECT_EQ(ErrorOf([&] { params.RejectUnknown(); }), "");
  // Another node's keys and the root's are not this node's business.
  ParamReader sim(Tree(), "sim/");
  sim.Get("stamp_offset", 1.0);
  EXPECT_EQ(ErrorOf([&] { sim.RejectUnknown(); }), "");
  EXPECT_EQ(sim.Resolve("rate"), "/sim/rate");
}

}  // namespace
}  // namespace aar_ros_common
