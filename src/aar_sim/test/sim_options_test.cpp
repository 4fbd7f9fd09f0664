// The simulator's parameters through LoadSimNodeOptions over a parameter tree (no master): the
// turbulence and sensor keys (config/sim.yaml "# Turbulence", "# Sensor") are read, default to
// the ideal world, and values out of range are refused naming the key.
#include <gtest/gtest.h>

#include <string>
#include <tuple>
#include <vector>

#include <aar_ros_common/param_reader.h>

#include "aar_sim/ros/sim_node.h"

namespace aar_sim {
namespace {

using XmlRpc::XmlRpcValue;

// /sim with a flight path and `key: value`.
aar_ros_common::ParamReader Params(XmlRpcValue& tree, const std::string& key = "",
                                   const XmlRpcValue& value = XmlRpcValue()) {
  tree = XmlRpcValue();
  tree["sim"]["flight_path"] = "approach_default.csv";
  if (!key.empty()) tree["sim"][key] = value;
  return aar_ros_common::ParamReader(tree, "/sim");
}

TEST(SimOptions, TurbulenceOffByDefault) {
  XmlRpcValue tree;
  auto params = Params(tree);
  const SimNodeOptions o = LoadSimNodeOptions(params);
  EXPECT_EQ(o.turbulence.intensity, TurbulenceIntensity::kNone);
  EXPECT_EQ(o.turbulence.seed, 1u);
  EXPECT_EQ(o.turbulence.airspeed, 130.0);
  EXPECT_EQ(o.turbulence.altitude, 6000.0);
}

TEST(SimOptions, TurbulenceKeysRead) {
  XmlRpcValue tree;
  auto params = Params(tree, "turbulence", XmlRpcValue("severe"));
  tree["sim"]["turbulence_seed"] = 17;
  tree["sim"]["turbulence_airspeed"] = 120.5;
  tree["sim"]["turbulence_altitude"] = 8000;
  params = aar_ros_common::ParamReader(tree, "/sim");
  const SimNodeOptions o = LoadSimNodeOptions(params);
  EXPECT_EQ(o.turbulence.intensity, TurbulenceIntensity::kSevere);
  EXPECT_EQ(o.turbulence.seed, 17u);
  EXPECT_EQ(o.turbulence.airspeed, 120.5);
  EXPECT_EQ(o.turbulence.altitude, 8000.0);
  EXPECT_NO_THROW(CheckTurbulenceOptions(o.turbulence));
}

TEST(SimOptions, BadTurbulenceValuesRefusedNamingTheKey) {
  const std::vector<std::pair<std::string, XmlRpcValue>> bad = {
      {"turbulence", XmlRpcValue("strong")},         {"turbulence", XmlRpcValue(2)},
      {"turbulence_seed", XmlRpcValue(-1)},          {"turbulence_airspeed", XmlRpcValue(-130.0)},
      {"turbulence_airspeed", XmlRpcValue(0.0)},     {"turbulence_altitude", XmlRpcValue(-100.0)},
      {"turbulence_altitude", XmlRpcValue(300.0)},  // the low-altitude model: not implemented
      {"turbulence_altitude", XmlRpcValue(30000.0)}, {"turbulence_altitude", XmlRpcValue("high")},
  };
  for (const auto& [key, value] : bad) {
    XmlRpcValue tree;
    auto params = Params(tree, key, value);
    try {
      LoadSimNodeOptions(params);
      ADD_FAILURE() << key << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("/sim/" + key + " "), std::string::npos) << e.what();
    }
  }
}

XmlRpc::XmlRpcValue Tree() {
  XmlRpc::XmlRpcValue tree;
  tree["sim"]["flight_path"] = std::string("/path/approach.csv");  // not opened by the loader
  return tree;
}

SimNodeOptions Load(const XmlRpc::XmlRpcValue& tree) {
  aar_ros_common::ParamReader params(tree, "/sim");
  return LoadSimNodeOptions(params);
}

std::string ErrorOf(const XmlRpc::XmlRpcValue& tree) {
  try {
    Load(tree);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SimOptions, SensorDefaultsToTheIdealCamera) {
  const SensorOptions s = Load(Tree()).world.sensor, ideal;
  EXPECT_EQ(s.noise_stddev, 0.0);
  EXPECT_EQ(s.full_well, 0.0);
  EXPECT_FALSE(s.motion_blur);
  EXPECT_EQ(s.gain_mismatch, 0.0);
  EXPECT_FALSE(s.auto_exposure);
  EXPECT_EQ(s.exposure_time, ideal.exposure_time);
}

TEST(SimOptions, SensorKeysAreRead) {
  XmlRpc::XmlRpcValue tree = Tree();
  XmlRpc::XmlRpcValue& sim = tree["sim"];
  sim["noise_stddev"] = 2.0;
  sim["noise_seed"] = 9;
  sim["full_well"] = 10000.0;
  sim["motion_blur"] = true;
  sim["exposure_time"] = 0.004;
  sim["gain_mismatch"] = -0.02;
  sim["auto_exposure"] = true;
  sim["exposure_target"] = 100.0;
  sim["exposure_gain_min"] = 0.5;
  sim["exposure_gain_max"] = 2;  // an int is a number too
  const SensorOptions s = Load(tree).world.sensor;
  EXPECT_EQ(s.noise_stddev, 2.0);
  EXPECT_EQ(s.noise_seed, 9u);
  EXPECT_EQ(s.full_well, 10000.0);
  EXPECT_TRUE(s.motion_blur);
  EXPECT_EQ(s.exposure_time, 0.004);
  EXPECT_EQ(s.gain_mismatch, -0.02);
  EXPECT_TRUE(s.auto_exposure);
  EXPECT_EQ(s.exposure_target, 100.0);
  EXPECT_EQ(s.exposure_gain_min, 0.5);
  EXPECT_EQ(s.exposure_gain_max, 2.0);
  EXPECT_NO_THROW(s.Validate());
}

TEST(SimOptions, SensorValuesOutOfRangeAreRefusedNamingTheKey) {
  for (const auto& [key, value, text] :
       std::vector<std::tuple<std::string, XmlRpc::XmlRpcValue, std::string>>{
           {"exposure_time", 0.0,
            "parameter /sim/exposure_time must be positive: an exposure of "
            "zero (or less) collects no light"},
           {"exposure_time", -0.002, "parameter /sim/exposure_time must be positive"},
           {"exposure_time", 2.0, "parameter /sim/exposure_time must be at most 1 s"},
           {"full_well", -1.0, "parameter /sim/full_well must not be negative"},
           {"noise_stddev", -0.5, "parameter /sim/noise_stddev must not be negative"},
           {"gain_mismatch", 0.5, "parameter /sim/gain_mismatch must be within (-0.5, 0.5)"},
           {"exposure_target", 0.0, "parameter /sim/exposure_target must be in (0, 255)"},
           {"exposure_target", 255.0, "parameter /sim/exposure_target must be in (0, 255)"},
           {"exposure_gain_min", 0.0, "parameter /sim/exposure_gain_min must be positive"},
           {"exposure_gain_max", 0.1,
            "parameter /sim/exposure_gain_max must not be below exposure_gain_min"},
           {"motion_blur", std::string("yes"), "/sim/motion_blur"},
           {"exposure_time", std::string("2 ms"), "/sim/exposure_time"},
       }) {
    XmlRpc::XmlRpcValue tree = Tree();
    tree["sim"][key] = value;
    const std::string error = ErrorOf(tree);
    EXPECT_NE(error.find(text), std::string::npos) << key << ": " << error;
  }
  // The core refuses the same, naming the field (a World built without the loader).
  SensorOptions zero;
  zero.exposure_time = 0.0;
  try {
    zero.Validate();
    ADD_FAILURE() << "an exposure of zero was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sensor option exposure_time"), std::string::npos);
  }
}

// ~rigs: absent, the one rig of the top-level mount; a second rig takes the top-level keys it
// does not set; the first must be stereo, names unique and well formed, keys the mount's.
TEST(SimOptions, RigsAfterTheFirstTakeTheTopLevelKeysTheyDoNotSet) {
  XmlRpc::XmlRpcValue tree = Tree();
  const SimNodeOptions one = Load(tree);
  EXPECT_TRUE(one.more_rigs.empty());
  tree["sim"]["camera_z"] = -4.0;
  XmlRpc::XmlRpcValue first, second;
  first["name"] = std::string("stereo");
  second["name"] = std::string("share_mirror");
  second["camera_x"] = -15.0;
  second["camera_y"] = -1;  // an int is a number too
  tree["sim"]["rigs"][0] = first;
  tree["sim"]["rigs"][1] = second;
  const SimNodeOptions two = Load(tree);
  ASSERT_EQ(two.more_rigs.size(), 1u);
  EXPECT_EQ(two.more_rigs[0].name, "share_mirror");
  const Eigen::Vector3d centre = two.more_rigs[0].rig.T_tanker_left_optical *
                                 Eigen::Vector3d(0.5 * two.more_rigs[0].rig.baseline, 0.0, 0.0);
  EXPECT_TRUE(centre.isApprox(Eigen::Vector3d(-15.0, -1.0, -4.0), 1e-12)) << centre.transpose();
  EXPECT_TRUE(two.world.rig.T_tanker_left_optical.isApprox(
      MakeStereoRig(two.world.rig.intrinsics, 0.5, {-20.0, 1.0, -4.0}).T_tanker_left_optical));
  EXPECT_TRUE(two.more_rigs[0].rig.T_tanker_left_optical.linear().isApprox(
      two.world.rig.T_tanker_left_optical.linear()));  // looking the same way
  XmlRpc::XmlRpcValue bad = second;
  bad["camera_w"] = 1.0;
  for (const auto& [rigs, text] :
       std::vector<std::pair<std::vector<XmlRpc::XmlRpcValue>, std::string>>{
           {{second}, "the first rig is stereo"},
           {{first, first}, "names rig stereo twice"},
           {{first, bad}, "rig share_mirror: unknown key camera_w"},
       }) {
    XmlRpc::XmlRpcValue t = Tree();
    for (size_t i = 0; i < rigs.size(); ++i) t["sim"]["rigs"][int(i)] = rigs[i];
    EXPECT_NE(ErrorOf(t).find("/sim/rigs " + text), std::string::npos) << ErrorOf(t);
  }
  XmlRpc::XmlRpcValue t = Tree();
  XmlRpc::XmlRpcValue odd = second;
  odd["name"] = std::string("2nd rig");
  t["sim"]["rigs"][0] = first;
  t["sim"]["rigs"][1] = odd;
  EXPECT_NE(ErrorOf(t).find("a name is a letter"), std::string::npos) << ErrorOf(t);
  t = Tree();
  t["sim"]["rigs"] = std::string("stereo");
  EXPECT_NE(ErrorOf(t).find("/sim/rigs must be a list"), std::string::npos) << ErrorOf(t);
}

}  // namespace
}  // namespace aar_sim
