// Every node YAML in config/ and every experiment in config/experiments/, loaded as the pipeline
// loads them (defaults first, the experiment over them), passes the nodes' own option loaders,
// which refuse unknown keys and wrong types.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <tuple>
#include <vector>

#include <aar_eval/ros/eval_node.h>
#include <aar_occlusion/ros/occlusion_node.h>
#include <aar_registration/ros/registration_node.h>
#include <aar_ros_common/param_reader.h>
#include <aar_sim/ros/sim_node.h>
#include <aar_stereo/ros/stereo_node.h>
#include <ros/ros.h>

#include "aar_testing/paths.h"

namespace {

TEST(Config, EveryExperimentLoadsIntoEveryNode) {
  const std::string dir = aar_testing::ConfigDir() + "/experiments";
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
      const ros::NodeHandle stereo_nh(root, "stereo/aar_stereo");
      // The matcher by name (config/stereo.yaml: block_matching; tracking_outline: sparse).
      const aar_ros_common::ParamReader stereo_params(stereo_nh);
      const int matcher = aar_stereo::LoadStereoConfig(stereo_params).matcher;
      const auto stereo = aar_stereo::LoadStereoNodeOptions(stereo_nh);
      // What the experiments claim in their comments.
      if (name == "dynamic") {
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kVolumes);
        EXPECT_TRUE(occlusion.step.build_reference);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kTopic);
      }
      if (name == "static_wings_nose") {
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kRaysBrute);
        EXPECT_TRUE(occlusion.step.boom.cull_behind_boom);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kWingsNose);
      }
      const bool flight = name == "flight" || name == "flight_no_boom" ||
                          name == "flight_both_views" || name == "flight_partial" ||
                          name == "flight_two_rigs";
      // flight_two_rigs: flight's settings on a second rig at config/mounts/share_mirror.yaml,
      // whose stages take the experiment's settings as the first rig's do.
      const bool two_rigs = name == "flight_two_rigs";
      EXPECT_EQ(registration.rigs.size(), two_rigs ? 2u : 1u) << name;
      EXPECT_EQ(sim.more_rigs.size(), two_rigs ? 1u : 0u) << name;
      if (two_rigs) {
        ASSERT_EQ(sim.more_rigs.size(), 1u);
        EXPECT_EQ(sim.more_rigs[0].name, "share_mirror");
        EXPECT_EQ(registration.rigs[1], "share_mirror");
        const ros::NodeHandle rig_stereo(root, "share_mirror/aar_stereo");
        const auto rig_occlusion = aar_occlusion::LoadOcclusionNodeOptions(
            ros::NodeHandle(root, "share_mirror/occlusion"));
        EXPECT_EQ(aar_stereo::LoadStereoNodeOptions(rig_stereo).roi.enabled, stereo.roi.enabled);
        EXPECT_EQ(rig_occlusion.step.cull, occlusion.step.cull);
        EXPECT_EQ(rig_occlusion.step.gate_receiver, occlusion.step.gate_receiver);
      }
      const bool outline = name == "tracking_outline" || flight;
      const bool ours = name == "tracking" || name == "tracking_robust" || outline;
      const bool robust = name == "tracking_robust" || outline;
      // tracking_outline: tracking_robust and the outline; flight: tracking_outline's settings
      // (FlightHoldsTrackingOutlinesSettings); nothing else has the outline.
      EXPECT_EQ(registration.registrar.outline.enabled, outline) << name;
      EXPECT_EQ(matcher, outline ? aar_stereo::Stereo_sparse : aar_stereo::Stereo_block_matching)
          << name;
      int on_server = -1;  // as dynamic_reconfigure reads it: the number
      EXPECT_TRUE(stereo_nh.getParam("matcher", on_server)) << name;
      EXPECT_EQ(on_server, matcher) << name;
      // flight_no_boom: flight with the boom hidden and modelled by no stage.
      EXPECT_EQ(sim.world.boom_visible, name != "flight_no_boom" && name != "no_boom") << name;
      EXPECT_EQ(occlusion.step.model_boom, name != "flight_no_boom") << name;
      EXPECT_EQ(registration.model_boom, name != "flight_no_boom") << name;
      EXPECT_EQ(stereo.roi.include_boom, name != "flight_no_boom") << name;
      // flight_both_views: flight whose start from the images searches both cameras;
      // flight_partial: that, starting from 30 % of a view's outline instead of 60 %.
      const bool partial = name == "flight_partial";
      EXPECT_EQ(registration.registrar.outline.acquisition.both_views,
                name == "flight_both_views" || partial)
          << name;
      EXPECT_EQ(registration.registrar.outline.acquisition.min_visible, partial ? 0.3 : 0.6)
          << name;
      EXPECT_EQ(registration.registrar.outline.partial_below, partial ? 0.6 : 0.0) << name;
      EXPECT_EQ(registration.registrar.outline.partial_range_sigmas, partial ? 3.0 : 0.0) << name;
      EXPECT_EQ(registration.registrar.outline.range_all_starts, partial) << name;
      EXPECT_EQ(registration.registrar.outline.partial_range_min_points, partial ? 3 : 10) << name;
      // Stereo's cue: flight_two_rigs and flight_partial; its range, flight_partial.
      const aar_alignment::AcquisitionOptions& acquisition =
          registration.registrar.outline.acquisition;
      EXPECT_EQ(acquisition.cue_min_points, partial || name == "flight_two_rigs" ? 10 : 0) << name;
      EXPECT_EQ(acquisition.cue_disparity_margin_px, partial ? 1.0 : 0.0) << name;
      if (outline) {
        EXPECT_EQ(registration.registrar.outline.disparity_sigma, 0.25);
      } else {
        EXPECT_EQ(registration.registrar.outline.disparity_sigma, 0.0) << name;
      }
      if (robust) {  // tracking, with a robust seed and the propellers culled
        EXPECT_EQ(registration.registrar.seed_points, aar_registration::SeedPoints::kDensestBall);
        EXPECT_EQ(occlusion.step.seed_points, aar_geometry::SeedPoints::kDensestBall);
        EXPECT_TRUE(occlusion.step.cull_propellers);
        EXPECT_EQ(occlusion.step.propellers.size(), 2u);  // the C-12's, from its description
        EXPECT_TRUE(occlusion.step.gate_receiver);
        EXPECT_EQ(occlusion.step.gate_margin, 3.0);
      } else {
        EXPECT_EQ(registration.registrar.seed_points, aar_registration::SeedPoints::kAll) << name;
        EXPECT_EQ(occlusion.step.seed_points, aar_geometry::SeedPoints::kAll) << name;
        EXPECT_FALSE(occlusion.step.cull_propellers) << name;
        EXPECT_FALSE(occlusion.step.gate_receiver) << name;
      }
      if (ours) {  // the dynamic experiment's stages, then a tracker
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kVolumes);
        EXPECT_TRUE(occlusion.step.build_reference);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kTopic);
        EXPECT_TRUE(registration.registrar.track);
        EXPECT_EQ(registration.registrar.seed, aar_registration::SeedMode::kPrediction);
        EXPECT_TRUE(stereo.roi.enabled);
      } else {
        EXPECT_FALSE(registration.registrar.track) << name << " is a thesis experiment";
        EXPECT_FALSE(stereo.roi.enabled) << name << " is a thesis experiment";
        EXPECT_FALSE(occlusion.extrapolate_estimate) << name << " is a thesis experiment";
      }
      if (name == "culling_only") {  // dynamic's culling, naive's reference
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kVolumes);
        EXPECT_FALSE(occlusion.step.build_reference);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kShelled);
      }
      if (name == "dynamic_reference_only") {  // dynamic's reference, naive's cloud
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kNone);
        EXPECT_TRUE(occlusion.step.build_reference);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kTopic);
      }
      if (!ours) {  // the thesis's ICP: every point paired, stop when RMS stalls
        EXPECT_EQ(registration.registrar.icp.max_correspondence_distance, 0.0) << name;
        EXPECT_EQ(registration.registrar.icp.min_rms_improvement, 0.0) << name;
        EXPECT_TRUE(registration.registrar.icp.stop_on_rms_rise) << name;
        EXPECT_EQ(registration.registrar.icp.max_iterations, 30) << name;
      }
      if (name == "naive" || name == "no_boom") {
        EXPECT_EQ(occlusion.step.cull, aar_occlusion::CullMethod::kNone);
        EXPECT_EQ(registration.registrar.reference, aar_registration::ReferenceKind::kShelled);
        EXPECT_EQ(sim.world.boom_visible, name == "naive");
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << "experiment " << name << ": " << e.what();
    }
  }
  // The thesis's four, tracking, tracking_robust, tracking_outline, flight, flight_no_boom,
  // flight_both_views, flight_partial, flight_two_rigs, the two ablations.
  EXPECT_EQ(experiments, 14);
}

// Every camera mount in config/mounts/ loads into the simulator over config/sim.yaml and moves
// only the rig: thesis_share is 5 m further forward and 1 m lower than the default mount,
// share_mirror the same on the boom's other side (2 m right).
TEST(Config, EveryCameraMountLoadsIntoTheSim) {
  const std::string dir = aar_testing::ConfigDir() + "/mounts";
  int mounts = 0;
  const auto base = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    ++mounts;
    ros::NodeHandle root("/mount_" + name);
    ASSERT_TRUE(root.hasParam("sim")) << name << ": not loaded by config.test (add it there)";
    try {
      const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle(root, "sim"));
      const Eigen::Vector3d moved = sim.world.rig.T_tanker_left_optical.translation() -
                                    base.world.rig.T_tanker_left_optical.translation();
      if (name == "thesis_share") {  // EXPECT_* is an if-else inside
        EXPECT_LT((moved - Eigen::Vector3d(5.0, 0.0, -1.0)).norm(), 1e-9);
      } else if (name == "share_mirror") {
        EXPECT_LT((moved - Eigen::Vector3d(5.0, -2.0, -1.0)).norm(), 1e-9);
      }
      EXPECT_TRUE(sim.world.rig.T_tanker_left_optical.linear().isApprox(
          base.world.rig.T_tanker_left_optical.linear()));
    } catch (const std::exception& e) {
      ADD_FAILURE() << "mount " << name << ": " << e.what();
    }
  }
  EXPECT_EQ(mounts, 2);
}

// The turbulence preset loads into the simulator over config/sim.yaml and turns on moderate
// turbulence; config/sim.yaml alone keeps it off (the ideal world).
TEST(Config, TurbulencePresetLoadsIntoTheSim) {
  try {
    const auto base = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
    EXPECT_EQ(base.turbulence.intensity, aar_sim::TurbulenceIntensity::kNone);
    const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/realism_turbulence/sim"));
    EXPECT_EQ(sim.turbulence.intensity, aar_sim::TurbulenceIntensity::kModerate);
    EXPECT_NO_THROW(aar_sim::CheckTurbulenceOptions(sim.turbulence));
  } catch (const std::exception& e) {
    ADD_FAILURE() << "realism/turbulence.yaml: " << e.what();
  }
}

TEST(Config, StereoAndEvalLoadAsTheLaunchFilesGiveThem) {
  try {
    const auto stereo = aar_stereo::LoadStereoNodeOptions(ros::NodeHandle("/stereo/aar_stereo"));
    EXPECT_FALSE(stereo.approximate_sync);
    EXPECT_EQ(stereo.queue_size, 5);
    const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
    const auto eval = aar_eval::LoadEvalNodeOptions(ros::NodeHandle("/eval"));
    EXPECT_EQ(eval.output_dir, "/tmp/aar_config_test");
    EXPECT_EQ(eval.expected_frames, 509);
    EXPECT_EQ(eval.stamp_offset, sim.stamp_offset);  // read where the simulator is configured
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  // A misspelt key in stereo.yaml's namespace stops the node, naming it.
  ros::NodeHandle("/stereo/aar_stereo").setParam("block_sise", 11);
  try {
    aar_stereo::LoadStereoNodeOptions(ros::NodeHandle("/stereo/aar_stereo"));
    ADD_FAILURE() << "a misspelt stereo key was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/stereo/aar_stereo/block_sise"), std::string::npos)
        << e.what();
  }
}

// config/registration.yaml documents every key at the options struct's value: loading it changes
// nothing (the experiments' results do not depend on whether a launch loads it).
TEST(Config, RegistrationYamlHoldsTheStructsDefaults) {
  aar_ros_common::ParamReader none(XmlRpc::XmlRpcValue(), "/none");
  const auto bare = aar_registration::LoadRegistrationNodeOptions(none);
  // Every key the loader reads is in the file, but those whose default is not one number: the
  // receiver (the launch files give it), the nominal pose (the receiver's contact pose) and the
  // outline's start rotation (kept in radians by the struct).
  const std::set<std::string> not_in_yaml = {
      "receiver",         "nominal_x",
      "nominal_y",        "nominal_z",
      "nominal_roll_deg", "nominal_pitch_deg",
      "nominal_yaw_deg",  "outline_start_sigma_rotation_deg"};
  XmlRpc::XmlRpcValue file;
  ASSERT_TRUE(ros::NodeHandle("/registration").getParam("", file));
  for (const auto& key : none.known_keys()) {
    if (!not_in_yaml.count(key)) EXPECT_TRUE(file.hasMember(key)) << key << " not in the YAML";
  }
  const auto yaml = aar_registration::LoadRegistrationNodeOptions(ros::NodeHandle("/registration"));
  const auto &b = bare.registrar, &y = yaml.registrar;
  EXPECT_EQ(y.reference, b.reference);
  EXPECT_EQ(y.sampling.points_per_m2, b.sampling.points_per_m2);
  EXPECT_EQ(y.sampling.seed, b.sampling.seed);
  EXPECT_EQ(y.sampling.visibility_tolerance, b.sampling.visibility_tolerance);
  EXPECT_TRUE(y.T_tanker_receiver_nominal.isApprox(b.T_tanker_receiver_nominal, 0.0));
  EXPECT_EQ(y.icp.metric, b.icp.metric);
  EXPECT_EQ(y.icp.max_iterations, b.icp.max_iterations);
  EXPECT_EQ(y.icp.max_correspondence_distance, b.icp.max_correspondence_distance);
  EXPECT_EQ(y.icp.min_rms_improvement, b.icp.min_rms_improvement);
  EXPECT_EQ(y.icp.stop_on_rms_rise, b.icp.stop_on_rms_rise);
  EXPECT_EQ(y.icp.rms_epsilon, b.icp.rms_epsilon);
  EXPECT_EQ(y.icp.independent_correspondences, b.icp.independent_correspondences);
  EXPECT_EQ(y.icp.stereo.ray_sigma_coefficient, b.icp.stereo.ray_sigma_coefficient);
  EXPECT_EQ(y.icp.stereo.plane_sigma, b.icp.stereo.plane_sigma);
  EXPECT_EQ(y.icp.stereo.ray_reach, b.icp.stereo.ray_reach);
  EXPECT_EQ(y.seed, b.seed);
  EXPECT_EQ(y.seed_points, b.seed_points);
  EXPECT_EQ(y.previous_max_age, b.previous_max_age);
  EXPECT_EQ(y.max_sensed_points, b.max_sensed_points);
  EXPECT_EQ(y.subsample_seed, b.subsample_seed);
  EXPECT_EQ(y.max_cloud_points, b.max_cloud_points);
  EXPECT_EQ(y.track, b.track);
  EXPECT_EQ(y.gate.min_fitness, b.gate.min_fitness);
  EXPECT_EQ(y.gate.max_rms, b.gate.max_rms);
  EXPECT_EQ(y.tracker.acceleration_sigma, b.tracker.acceleration_sigma);
  EXPECT_EQ(y.tracker.angular_acceleration_sigma, b.tracker.angular_acceleration_sigma);
  EXPECT_EQ(y.tracker.initial_velocity_sigma, b.tracker.initial_velocity_sigma);
  EXPECT_EQ(y.tracker.initial_angular_velocity_sigma, b.tracker.initial_angular_velocity_sigma);
  EXPECT_EQ(y.tracker.gate_chi2, b.tracker.gate_chi2);
  EXPECT_EQ(y.tracker.max_rejections, b.tracker.max_rejections);
  EXPECT_EQ(y.tracker.max_coast_s, b.tracker.max_coast_s);
  EXPECT_EQ(y.tracker.maneuver_acceleration_sigma, b.tracker.maneuver_acceleration_sigma);
  EXPECT_EQ(y.tracker.maneuver_angular_acceleration_sigma,
            b.tracker.maneuver_angular_acceleration_sigma);
  EXPECT_EQ(y.tracker.steady_sojourn_s, b.tracker.steady_sojourn_s);
  EXPECT_EQ(y.tracker.maneuver_sojourn_s, b.tracker.maneuver_sojourn_s);
  const auto &yo = y.outline, &bo = b.outline;
  EXPECT_EQ(yo.enabled, bo.enabled);
  EXPECT_EQ(yo.min_quality, bo.min_quality);
  EXPECT_EQ(yo.max_poor_frames, bo.max_poor_frames);
  EXPECT_EQ(yo.start_candidates, bo.start_candidates);
  EXPECT_EQ(yo.maneuver_quality, bo.maneuver_quality);
  EXPECT_EQ(yo.start_sigma_position, bo.start_sigma_position);
  EXPECT_EQ(yo.start_sigma_rotation, bo.start_sigma_rotation);
  EXPECT_EQ(yo.disparity_sigma, bo.disparity_sigma);
  EXPECT_EQ(yo.disparity_rotation, bo.disparity_rotation);
  EXPECT_EQ(yo.remove_prior, bo.remove_prior);
  EXPECT_EQ(yo.image_start, bo.image_start);
  EXPECT_EQ(yo.image_start_quality, bo.image_start_quality);
  EXPECT_EQ(yo.acquisition.min_range, bo.acquisition.min_range);
  EXPECT_EQ(yo.acquisition.max_range, bo.acquisition.max_range);
  EXPECT_EQ(yo.acquisition.range_step, bo.acquisition.range_step);
  EXPECT_EQ(yo.acquisition.min_visible, bo.acquisition.min_visible);
  EXPECT_EQ(yo.acquisition.both_views, bo.acquisition.both_views);
  EXPECT_EQ(yo.alignment.contour_points, bo.alignment.contour_points);
  EXPECT_EQ(yo.alignment.mask_size, bo.alignment.mask_size);
  EXPECT_EQ(yo.alignment.mask_max_scale, bo.alignment.mask_max_scale);
  EXPECT_EQ(yo.alignment.line_model, bo.alignment.line_model);
  EXPECT_EQ(yo.alignment.search_radius_px, bo.alignment.search_radius_px);
  EXPECT_EQ(yo.alignment.covariance_scale, bo.alignment.covariance_scale);
  EXPECT_EQ(yo.alignment.rigs_share_errors, bo.alignment.rigs_share_errors);
  EXPECT_EQ(y.persistent_error.pixel_sigma, b.persistent_error.pixel_sigma);
  EXPECT_EQ(y.fault_start_offset_m, b.fault_start_offset_m);
  const auto &yi = y.integrity, &bi = b.integrity;
  EXPECT_EQ(yi.integrity_risk, bi.integrity_risk);
  EXPECT_EQ(yi.overbound_factor, bi.overbound_factor);
  EXPECT_EQ(yi.position_bias_m, bi.position_bias_m);
  EXPECT_EQ(yi.attitude_bias_deg, bi.attitude_bias_deg);
  EXPECT_EQ(yi.confirm_frames, bi.confirm_frames);
  ASSERT_EQ(yi.bands.size(), bi.bands.size());
  for (size_t i = 0; i < yi.bands.size(); ++i) {
    EXPECT_EQ(yi.bands[i].max_range_m, bi.bands[i].max_range_m) << "band " << i;
    EXPECT_EQ(yi.bands[i].position_m, bi.bands[i].position_m) << "band " << i;
    EXPECT_EQ(yi.bands[i].attitude_deg, bi.bands[i].attitude_deg) << "band " << i;
    EXPECT_EQ(yi.bands[i].overbound_factor, bi.bands[i].overbound_factor) << "band " << i;
  }
  const auto &yc = yaml.common, &bc = bare.common;
  EXPECT_EQ(yc.frames.tanker, bc.frames.tanker);
  EXPECT_EQ(yc.frames.receiver, bc.frames.receiver);
  EXPECT_EQ(yc.frames.left_camera, bc.frames.left_camera);
  EXPECT_EQ(yc.frames.right_camera, bc.frames.right_camera);
  EXPECT_EQ(yc.robot_description, bc.robot_description);
  EXPECT_EQ(yc.tf_timeout, bc.tf_timeout);
  EXPECT_EQ(yc.tf_fallback_age, bc.tf_fallback_age);
  EXPECT_EQ(yc.diagnostic_period, bc.diagnostic_period);
  EXPECT_EQ(yaml.model_boom, bare.model_boom);
  EXPECT_EQ(yaml.truth_frame, bare.truth_frame);
  EXPECT_EQ(yaml.newest_wins, bare.newest_wins);
  EXPECT_EQ(yaml.reference_timeout, bare.reference_timeout);
  EXPECT_EQ(yaml.max_stamp_lead, bare.max_stamp_lead);
  // Registration reads no estimate: estimate_max_age is not one of its keys.
  ros::NodeHandle("/registration").setParam("estimate_max_age", 1.0);
  EXPECT_THROW(aar_registration::LoadRegistrationNodeOptions(ros::NodeHandle("/registration")),
               std::invalid_argument);
  ros::NodeHandle("/registration").deleteParam("estimate_max_age");
}

// Every realism preset in config/realism/ loads into the simulator over config/sim.yaml, as
// pipeline.launch's sim_config loads it. config/sim.yaml's sensor is the ideal camera
// (docs/realism/sensor.md); realism/sensor.yaml turns each sensor effect on.
TEST(Config, EveryRealismPresetLoadsIntoTheSim) {
  try {
    const aar_sim::SensorOptions ideal,
        s = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim")).world.sensor;
    EXPECT_EQ(s.noise_stddev, ideal.noise_stddev);
    EXPECT_EQ(s.full_well, ideal.full_well);
    EXPECT_EQ(s.motion_blur, ideal.motion_blur);
    EXPECT_EQ(s.gain_mismatch, ideal.gain_mismatch);
    EXPECT_EQ(s.auto_exposure, ideal.auto_exposure);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  const std::string dir = aar_testing::ConfigDir() + "/realism";
  int presets = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    ++presets;
    ros::NodeHandle root("/realism_" + name);
    ASSERT_TRUE(root.hasParam("sim")) << name << ": not loaded by config.test (add it there)";
    try {
      const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle(root, "sim"));
      if (name == "sensor") {  // EXPECT_* is an if-else inside
        const aar_sim::SensorOptions& s = sim.world.sensor;
        EXPECT_EQ(s.noise_stddev, 2.0);
        EXPECT_EQ(s.full_well, 10000.0);
        EXPECT_TRUE(s.motion_blur);
        EXPECT_EQ(s.exposure_time, 0.002);
        EXPECT_EQ(s.gain_mismatch, 0.03);
        EXPECT_TRUE(s.auto_exposure);
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << "preset " << name << ": " << e.what();
    }
  }
  EXPECT_GE(presets, 1);
}

// realism/realistic.yaml is every effect at once at the level of its own preset: each key of
// every other preset has the same value there, so the two cannot drift apart.
TEST(Config, RealisticPresetHoldsEveryOtherPresetsValues) {
  const std::string dir = aar_testing::ConfigDir() + "/realism";
  int keys = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().stem().string();
    if (entry.path().extension() != ".yaml" || name == "realistic") continue;
    std::ifstream file(entry.path());
    const std::regex key_line("^([a-z_]+):");
    std::smatch m;
    for (std::string line; std::getline(file, line);) {
      if (!std::regex_search(line, m, key_line)) continue;
      XmlRpc::XmlRpcValue preset, realistic;
      ASSERT_TRUE(ros::param::get("/realism_" + name + "/sim/" + m[1].str(), preset)) << m[1];
      EXPECT_TRUE(ros::param::get("/realism_realistic/sim/" + m[1].str(), realistic) &&
                  realistic == preset)
          << "realistic.yaml's " << m[1] << " differs from " << name << ".yaml's";
      ++keys;
    }
  }
  EXPECT_GE(keys, 30);  // 6 background + 9 sensor + 4 turbulence + 10 sun + 1 propeller keys
}

// Each case's key, set alone to its value on `node` (over the parameters already there), makes
// the simulator's loader refuse with a message that contains the case's text.
void ExpectSimRefuses(
    ros::NodeHandle& node,
    const std::vector<std::tuple<std::string, XmlRpc::XmlRpcValue, std::string>>& cases) {
  for (const auto& [key, value, text] : cases) {
    node.setParam(key, value);
    try {
      aar_sim::LoadSimNodeOptions(node);
      ADD_FAILURE() << key << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
    node.deleteParam(key);
  }
}

// config/sim.yaml's raw cameras: off by default (rectified pinhole images), and its lens values
// are the ones the code documents (aar_sim::DefaultRawCameraOptions). A lens list of the wrong
// length or type stops the simulator, naming the key.
TEST(Config, SimRawCamerasOffByDefaultLensesAsDocumented) {
  try {
    const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
    const aar_sim::RawCameraOptions defaults = aar_sim::DefaultRawCameraOptions();
    EXPECT_FALSE(sim.world.raw.enabled);
    EXPECT_EQ(sim.world.raw.left.distortion, defaults.left.distortion);
    EXPECT_EQ(sim.world.raw.right.distortion, defaults.right.distortion);
    EXPECT_TRUE(sim.world.raw.left.rotation_deg.isApprox(defaults.left.rotation_deg));
    EXPECT_TRUE(sim.world.raw.right.rotation_deg.isApprox(defaults.right.rotation_deg));
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  ros::NodeHandle raw("/sim_raw_bad");
  std::string path;
  ros::NodeHandle("/sim").getParam("flight_path", path);
  raw.setParam("flight_path", path);
  raw.setParam("raw_images", true);
  auto list = [](std::vector<XmlRpc::XmlRpcValue> items) {
    XmlRpc::XmlRpcValue value;
    value.setSize(static_cast<int>(items.size()));
    for (size_t i = 0; i < items.size(); ++i) value[static_cast<int>(i)] = items[i];
    return value;
  };
  ExpectSimRefuses(raw, {{"left_distortion", list({-0.2, 0.1, 0.0}),
                          "/sim_raw_bad/left_distortion must be a list of 5 numbers"},
                         {"right_rotation_deg", list({0.1, 0.2, std::string("x")}),
                          "/sim_raw_bad/right_rotation_deg must be a list of 3 numbers"},
                         {"left_rotation_deg", list({20.0, 0.0, 0.0}), "must stay within 10 deg"}});
  // Integers in a list are numbers too (YAML [0, 0, 0]).
  raw.setParam("left_rotation_deg", list({0, 1, 0}));
  try {
    EXPECT_NEAR(aar_sim::LoadSimNodeOptions(raw).world.raw.left.rotation_deg.y(), 1.0, 1e-12);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
}

// Issue 16 scene keys: off by default (the ideal world), the background preset turns terrain and
// clouds on, and bad values are refused naming the key.
TEST(Config, SceneBackgroundOffByDefaultPresetLoadsBadValuesRefused) {
  try {
    const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
    EXPECT_EQ(sim.world.renderer.scene.background, aar_sim::Background::kNone);
    const auto preset = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/realism_background/sim"));
    EXPECT_EQ(preset.world.renderer.scene.background, aar_sim::Background::kTerrain);
    EXPECT_GT(preset.world.renderer.scene.cloud_coverage, 0.0);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  ros::NodeHandle bad("/sim_scene_bad");
  std::string path;
  ros::NodeHandle("/sim").getParam("flight_path", path);
  bad.setParam("flight_path", path);
  ExpectSimRefuses(
      bad,
      {{"background", XmlRpc::XmlRpcValue("desert"), "/sim_scene_bad/background must be"},
       {"background_altitude", XmlRpc::XmlRpcValue(-1.0), "/sim_scene_bad/background_altitude"},
       {"visibility", XmlRpc::XmlRpcValue(0.0), "/sim_scene_bad/visibility"},
       {"cloud_coverage", XmlRpc::XmlRpcValue(1.5), "/sim_scene_bad/cloud_coverage"},
       {"cloud_altitude", XmlRpc::XmlRpcValue(5000.0), "/sim_scene_bad/cloud_altitude"},
       {"cloud_min_range", XmlRpc::XmlRpcValue(-3.0), "/sim_scene_bad/cloud_min_range"}});
}

// Issue 16 sun and propeller keys: off by default (the ideal world's light, no propellers), the
// presets turn them on, and out-of-range values (a sun below the horizon, say) are refused
// naming the key.
TEST(Config, SunAndPropellersOffByDefaultPresetsLoadBadValuesRefused) {
  try {
    const auto sim = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/sim"));
    EXPECT_FALSE(sim.world.renderer.sun.enabled);
    EXPECT_EQ(sim.world.propellers, aar_sim::PropellerMode::kNone);
    const auto sun = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/realism_sun/sim"));
    EXPECT_TRUE(sun.world.renderer.sun.enabled);
    EXPECT_TRUE(sun.world.renderer.sun.shadows);
    const auto props = aar_sim::LoadSimNodeOptions(ros::NodeHandle("/realism_propellers/sim"));
    EXPECT_EQ(props.world.propellers, aar_sim::PropellerMode::kBlades);
    EXPECT_EQ(props.world.receiver.propellers.size(), 2u);  // the C-12's, from c12.yaml
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  ros::NodeHandle bad("/sim_sun_bad");
  std::string path;
  ros::NodeHandle("/sim").getParam("flight_path", path);
  bad.setParam("flight_path", path);
  bad.setParam("sun", true);
  ExpectSimRefuses(
      bad,
      {{"sun_elevation_deg", XmlRpc::XmlRpcValue(-5.0),
        "/sim_sun_bad/sun_elevation_deg must be in (0, 90] deg: a sun at or below the horizon"},
       {"sun_elevation_deg", XmlRpc::XmlRpcValue(0.0), "/sim_sun_bad/sun_elevation_deg"},
       {"sun_direct", XmlRpc::XmlRpcValue(0.0), "/sim_sun_bad/sun_direct"},
       {"sun_ambient", XmlRpc::XmlRpcValue(-0.1), "/sim_sun_bad/sun_ambient"},
       {"sun_shadow_map_size", XmlRpc::XmlRpcValue(16), "/sim_sun_bad/sun_shadow_map_size"},
       {"sun_glass_specular", XmlRpc::XmlRpcValue(-1.0), "/sim_sun_bad/sun_glass_specular"},
       {"sun_shadows", XmlRpc::XmlRpcValue(3.0), "/sim_sun_bad/sun_shadows"},
       {"propellers", XmlRpc::XmlRpcValue("spinning"), "/sim_sun_bad/propellers must be one of"}});
}

// The receiver gate's keys: off by default, negative values refused naming the key.
TEST(Config, ReceiverGateOffByDefaultBadValuesRefused) {
  ros::NodeHandle good("/occlusion_gate");
  good.setParam("gate_receiver", true);
  good.setParam("gate_depth_coefficient", 0.0);
  try {
    EXPECT_FALSE(aar_occlusion::LoadOcclusionNodeOptions(ros::NodeHandle("/occlusion_default"))
                     .step.gate_receiver);
    const auto o = aar_occlusion::LoadOcclusionNodeOptions(good);
    EXPECT_TRUE(o.step.gate_receiver);
    EXPECT_EQ(o.step.gate_depth_coefficient, 0.0);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  for (const char* key : {"gate_margin", "gate_depth_coefficient"}) {
    ros::NodeHandle bad(std::string("/occlusion_gate_bad_") + key);
    bad.setParam(key, -1.0);
    try {
      aar_occlusion::LoadOcclusionNodeOptions(bad);
      ADD_FAILURE() << key << " = -1 was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad.getNamespace() + "/" + key), std::string::npos)
          << e.what();
    }
  }
}

// flight is tracking_outline's settings and the integrity's two covariance terms
// (docs/INTEGRITY.md) under the name users fly with, and flight_no_boom is flight with the boom
// hidden and modelled by no stage: every other key the same.
TEST(Config, FlightHoldsTrackingOutlinesSettings) {
  const auto tree = [](const std::string& experiment) {
    XmlRpc::XmlRpcValue value;
    EXPECT_TRUE(ros::NodeHandle("/experiment_" + experiment).getParam("", value)) << experiment;
    return value;
  };
  XmlRpc::XmlRpcValue outline = tree("tracking_outline"), flight = tree("flight"),
                      no_boom = tree("flight_no_boom");
  EXPECT_TRUE(static_cast<bool>(flight["registration"]["outline_disparity_rotation"]));
  EXPECT_EQ(static_cast<double>(flight["registration"]["persistent_pixel_sigma"]), 0.2);
  EXPECT_TRUE(static_cast<bool>(flight["registration"]["outline_remove_prior"]));
  EXPECT_EQ(static_cast<int>(flight["registration"]["outline_mask_size"]), 1408);
  EXPECT_EQ(static_cast<double>(flight["registration"]["outline_mask_max_scale"]), 1.0);
  EXPECT_EQ(static_cast<double>(flight["registration"]["integrity_attitude_envelope_deg"]), 15.0);
  // The keys flight sets beyond tracking_outline's, for its integrity (docs/INTEGRITY.md).
  const std::set<std::string> integrity = {
      "outline_disparity_rotation", "persistent_pixel_sigma", "outline_remove_prior",
      "outline_mask_size",          "outline_mask_max_scale", "integrity_attitude_envelope_deg",
      "alert_overbound_factor"};
  for (auto& [ns, keys] : flight) {
    if (ns != "registration") {
      EXPECT_TRUE(keys.toXml() == outline[ns].toXml()) << ns << ": flight differs";
      continue;
    }
    for (auto& [key, value] : keys) {
      if (integrity.count(key)) continue;
      EXPECT_TRUE(outline[ns].hasMember(key) && value.toXml() == outline[ns][key].toXml())
          << key << ": flight differs from tracking_outline";
    }
    EXPECT_EQ(keys.size(), outline[ns].size()) << "registration: keys tracking_outline lacks";
  }
  EXPECT_EQ(flight.size(), outline.size());
  EXPECT_FALSE(static_cast<bool>(no_boom["sim"]["boom"]));
  EXPECT_FALSE(static_cast<bool>(no_boom["occlusion"]["model_boom"]));
  EXPECT_FALSE(static_cast<bool>(no_boom["registration"]["model_boom"]));
  EXPECT_FALSE(static_cast<bool>(no_boom["stereo"]["aar_stereo"]["roi_include_boom"]));
  no_boom["sim"]["boom"] = true;
  XmlRpc::XmlRpcValue occlusion;
  for (auto& [key, value] : no_boom["occlusion"]) {
    if (key != "model_boom") occlusion[key] = value;
  }
  no_boom["registration"]["model_boom"] = true;                // config/registration.yaml's
  no_boom["stereo"]["aar_stereo"]["roi_include_boom"] = true;  // config/stereo.yaml's
  no_boom["occlusion"] = occlusion;
  // (Compared as text; a parameter tree is pages long: the keys that differ are named.)
  std::string differ;
  for (auto& [ns, keys] : flight) {
    const bool both = keys.getType() == XmlRpc::XmlRpcValue::TypeStruct && no_boom.hasMember(ns) &&
                      no_boom[ns].getType() == XmlRpc::XmlRpcValue::TypeStruct;
    if (!both) {
      if (!no_boom.hasMember(ns) || no_boom[ns].toXml() != keys.toXml()) differ += " " + ns;
      continue;
    }
    for (auto& [key, value] : keys)
      if (!no_boom[ns].hasMember(key) || no_boom[ns][key].toXml() != value.toXml())
        differ += " " + ns + "/" + key;
  }
  EXPECT_TRUE(no_boom.toXml() == flight.toXml()) << "flight_no_boom differs from flight:" << differ;
}

// `load` (a loader on `bad`) throws std::invalid_argument naming bad's `key` by its full name.
template <typename Load>
void ExpectRefusedByName(const ros::NodeHandle& bad, const std::string& key, Load load) {
  try {
    load();
    ADD_FAILURE() << bad.getNamespace() << "/" << key << " was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(bad.getNamespace() + "/" + key), std::string::npos)
        << e.what();
  }
}

// Issue 29's options are off unless asked for (the boom modelled, no depth margin, the thesis's
// point-to-point ICP); out-of-range values are refused naming the key.
TEST(Config, StereoRaysAndDepthMarginOffByDefaultBadValuesRefused) {
  try {
    const auto occlusion =
        aar_occlusion::LoadOcclusionNodeOptions(ros::NodeHandle("/occlusion_default"));
    EXPECT_EQ(occlusion.step.boom.cull_depth_coefficient, 0.0);
    EXPECT_TRUE(occlusion.step.model_boom);
    const auto registration = aar_registration::LoadRegistrationNodeOptions(
        ros::NodeHandle("/registration_outline_default"));
    EXPECT_EQ(registration.registrar.icp.metric, aar_registration::IcpMetric::kPointToPoint);
    EXPECT_TRUE(registration.model_boom);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  const std::vector<std::tuple<std::string, std::string, double>> bad_values = {
      {"occlusion", "cull_depth_coefficient", -0.001},
      {"registration", "icp_ray_sigma_coefficient", -0.001},
      {"registration", "icp_plane_sigma", 0.0},
      {"registration", "icp_ray_reach", -1.0}};
  for (const auto& [node, key, value] : bad_values) {
    ros::NodeHandle bad("/" + node + "_issue29_bad_" + key);
    bad.setParam(key, value);
    ExpectRefusedByName(bad, key, [&] {
      if (node == "occlusion") {
        aar_occlusion::LoadOcclusionNodeOptions(bad);
      } else {
        aar_registration::LoadRegistrationNodeOptions(bad);
      }
    });
  }
}

// The tracker's keys are refused under the names the YAML gives them (issue 31: a negative
// max_coast was refused as "max_coast_s", the C++ field's name, which no file has).
TEST(Config, TrackerKeysAreRefusedUnderTheirYamlNames) {
  const std::vector<std::pair<std::string, double>> bad_values = {
      {"max_coast", -1.0},          {"gate_chi2", 0.0},
      {"acceleration_sigma", -1.0}, {"initial_angular_velocity_sigma", 0.0},
      {"max_rejections", 0.0},      {"maneuver_acceleration_sigma", -1.0},
      {"maneuver_sojourn", 0.0},    {"steady_sojourn", -2.0}};
  for (const auto& [key, value] : bad_values) {
    ros::NodeHandle bad("/registration_issue31_bad_" + key);
    if (key == "max_rejections") {
      bad.setParam(key, static_cast<int>(value));
    } else {
      bad.setParam(key, value);
    }
    ExpectRefusedByName(bad, key, [&] { aar_registration::LoadRegistrationNodeOptions(bad); });
  }
}

// Integrity's keys (docs/INTEGRITY.md): out-of-range values, alert bands that do not rise, limit
// lists of the wrong length and a number where a list belongs are refused naming the key.
TEST(Config, IntegrityKeysAreRefusedUnderTheirYamlNames) {
  const std::vector<std::pair<std::string, XmlRpc::XmlRpcValue>> bad_values = {
      {"integrity_risk", XmlRpc::XmlRpcValue(0.0)},
      {"integrity_risk", XmlRpc::XmlRpcValue(1.0)},
      {"integrity_overbound_factor", XmlRpc::XmlRpcValue(0.5)},
      {"integrity_position_bias", XmlRpc::XmlRpcValue(-0.1)},
      {"integrity_confirm_frames", XmlRpc::XmlRpcValue(-1)},
      {"integrity_attitude_envelope_deg", XmlRpc::XmlRpcValue(-5.0)},
      {"integrity_attitude_envelope_deg", XmlRpc::XmlRpcValue(180.0)},
      {"persistent_pixel_sigma", XmlRpc::XmlRpcValue(-0.2)},
      {"alert_limit_position", XmlRpc::XmlRpcValue(2.0)},
      {"alert_overbound_factor", XmlRpc::XmlRpcValue(1.5)}};
  int n = 0;
  for (const auto& [key, value] : bad_values) {
    ros::NodeHandle bad("/registration_integrity_bad_" + std::to_string(n++));
    bad.setParam(key, value);
    ExpectRefusedByName(bad, key, [&] { aar_registration::LoadRegistrationNodeOptions(bad); });
  }
  const auto list = [](std::vector<double> values) {
    XmlRpc::XmlRpcValue v;
    v.setSize(static_cast<int>(values.size()));
    for (size_t i = 0; i < values.size(); ++i) v[static_cast<int>(i)] = values[i];
    return v;
  };
  ros::NodeHandle short_limits("/registration_integrity_bad_short");
  short_limits.setParam("alert_limit_position", list({0.5, 2.0}));
  ExpectRefusedByName(short_limits, "alert_limit_position",
                      [&] { aar_registration::LoadRegistrationNodeOptions(short_limits); });
  ros::NodeHandle falling("/registration_integrity_bad_falling");
  falling.setParam("alert_band_max_range", list({70.0, 38.0}));
  ExpectRefusedByName(falling, "alert_band_max_range",
                      [&] { aar_registration::LoadRegistrationNodeOptions(falling); });
}

// The outline (registration's `outline`, issue 27) is off unless asked for; out-of-range keys,
// and the outline without tracking, are refused naming the key.
TEST(Config, OutlineOffByDefaultBadValuesRefused) {
  try {
    EXPECT_FALSE(aar_registration::LoadRegistrationNodeOptions(
                     ros::NodeHandle("/registration_outline_default"))
                     .registrar.outline.enabled);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  const std::vector<std::pair<std::string, double>> bad_values = {
      {"outline_min_quality", 1.5},
      {"outline_maneuver_quality", -0.1},
      {"outline_max_poor_frames", 0},
      {"outline_start_sigma_position", 0.0},
      {"outline_disparity_sigma", -1.0},
      {"outline_contour_points", 4},
      {"outline_mask_size", 16},
      {"outline_mask_max_scale", 0.0},
      {"outline_covariance_scale", 0.0},
      {"outline_search_radius", -1.0},
      {"outline_start_candidates", 0},
      {"outline_image_start_quality", 1.5},
      {"outline_image_start_min_range", 0.0},
      {"outline_image_start_max_range", 10.0},
      {"outline_image_start_range_step", 1.0},
      {"outline_image_start_min_visible", 1.5},
      {"outline_image_start_partial_below", -0.1},
      {"outline_image_start_partial_confirm", -1},
      {"outline_image_start_partial_range_sigmas", -1.0},
      {"outline_image_start_partial_range_min_points", 0},
      {"outline_image_start_partial_range_independent_points", 0},
      {"outline_image_start_cue_min_points", -1},
      {"outline_image_start_cue_margin", -1.0},
      {"outline_image_start_cue_disparity_margin", -0.5}};
  for (const auto& [key, value] : bad_values) {
    ros::NodeHandle bad("/registration_outline_bad_" + key);
    bad.setParam("track", true);
    bad.setParam("outline", true);
    if (key == "outline_max_poor_frames" || key == "outline_contour_points" ||
        key == "outline_mask_size" || key == "outline_start_candidates" ||
        key == "outline_image_start_partial_confirm" ||
        key == "outline_image_start_partial_range_min_points" ||
        key == "outline_image_start_partial_range_independent_points" ||
        key == "outline_image_start_cue_min_points")
      bad.setParam(key, static_cast<int>(value));
    else
      bad.setParam(key, value);
    try {
      aar_registration::LoadRegistrationNodeOptions(bad);
      ADD_FAILURE() << key << " = " << value << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad.getNamespace() + "/" + key), std::string::npos)
          << e.what();
    }
  }
  ros::NodeHandle untracked("/registration_outline_untracked");
  untracked.setParam("outline", true);
  try {
    aar_registration::LoadRegistrationNodeOptions(untracked);
    ADD_FAILURE() << "the outline without tracking was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("needs track: true"), std::string::npos) << e.what();
  }
  // The range check on every start without the range check itself.
  ros::NodeHandle all_starts("/registration_outline_range_all");
  all_starts.setParam("track", true);
  all_starts.setParam("outline", true);
  all_starts.setParam("outline_start_range_all", true);
  ExpectRefusedByName(all_starts, "outline_start_range_all",
                      [&] { aar_registration::LoadRegistrationNodeOptions(all_starts); });
  // A misspelt `trak: true` is named as an unknown key, not as the outline needing tracking.
  ros::NodeHandle misspelt("/registration_outline_trak");
  misspelt.setParam("outline", true);
  misspelt.setParam("trak", true);
  ExpectRefusedByName(misspelt, "trak",
                      [&] { aar_registration::LoadRegistrationNodeOptions(misspelt); });
}

}  // namespace
