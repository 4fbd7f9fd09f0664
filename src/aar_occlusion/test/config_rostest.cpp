// Every node YAML in config/ and every experiment in config/experiments/, loaded as the pipeline
// loads them (defaults first, the experiment over them), passes the nodes' own option loaders,
// which refuse unknown keys and wrong types.
#include <gtest/gtest.h>

#include <filesystem>

#include <aar_registration/ros/registration_node.h>
#include <aar_sim/ros/sim_node.h>
#include <ros/ros.h>

#include "aar_occlusion/ros/occlusion_node.h"

namespace {

TEST(Config, EveryExperimentLoadsIntoEveryNode) {
  const std::string dir = std::string(AAR_CONFIG_DIR) + "/experiments";
  int experiments = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    ++experiments;
    ros::NodeHandle root("/experiment_" + name);
    ASSERT_TRUE(root.hasParam("sim")) << name << ": not loaded by config.test (add it there)";
    try {
      const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle(root, "sim"));
      const auto occlusion =
          aar_occlusion::LoadOcclusionNodeOptions(ros::NodeHandle(root, "occlusion"));
      const auto registration =
          aar_registration::LoadRegistrationNodeOptions(ros::NodeHandle(root, "registration"));
      // What the experiments claim in their comments.
      if (name == "dynamic") {
        EXPECT_EQ(occlusion.cull, aar_occlusion::CullMethod::kVolumes);
        EXPECT_TRUE(occlusion.publish_reference);
        EXPECT_EQ(registration.reference, aar_registration::ReferenceKind::kTopic);
      }
      if (name == "static_wings_nose") {
        EXPECT_EQ(occlusion.cull, aar_occlusion::CullMethod::kRaysBrute);
        EXPECT_TRUE(occlusion.boom.cull_behind_boom);
        EXPECT_EQ(registration.reference, aar_registration::ReferenceKind::kWingsNose);
      }
      if (name == "naive" || name == "no_boom") {
        EXPECT_EQ(occlusion.cull, aar_occlusion::CullMethod::kNone);
        EXPECT_EQ(registration.reference, aar_registration::ReferenceKind::kShelled);
        EXPECT_EQ(sim.world.boom_visible, name == "naive");
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << "experiment " << name << ": " << e.what();
    }
  }
  EXPECT_EQ(experiments, 4);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "config_rostest");
  return RUN_ALL_TESTS();
}
