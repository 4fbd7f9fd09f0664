// The node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <set>

#include <aar_geometry/pose.h>
#include <aar_ros_common/node_options.h>
#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/receiver_params.h>

#include "aar_registration/ros/registration_node.h"

namespace aar_registration {

namespace {

// The pose the shelled reference is seen from (~nominal_*).
Eigen::Isometry3d LoadNominalPose(aar_ros_common::ParamReader& params,
                                  const aar_description::ReceiverDescription& receiver) {
  // Nominal pose for shelling: the receiver's contact pose (its description's; else the C-12's
  // on the default approach).
  Eigen::Vector3d contact(-35.0, 0.0, -10.19), contact_rpy_deg(0.0, -2.0, 0.0);
  if (receiver.has_contact) {
    contact = receiver.T_tanker_receiver_contact.translation();
    contact_rpy_deg = receiver.contact_rpy_deg;
  }
  const Eigen::Vector3d nominal(params.Get("nominal_x", contact.x()),
                                params.Get("nominal_y", contact.y()),
                                params.Get("nominal_z", contact.z()));
  const aar_geometry::RollPitchYaw nominal_rpy{
      aar_geometry::DegToRad(params.Get("nominal_roll_deg", contact_rpy_deg.x())),
      aar_geometry::DegToRad(params.Get("nominal_pitch_deg", contact_rpy_deg.y())),
      aar_geometry::DegToRad(params.Get("nominal_yaw_deg", contact_rpy_deg.z()))};
  return aar_geometry::MakeTransform(nominal, nominal_rpy);
}

IcpOptions LoadIcpOptions(aar_ros_common::ParamReader& params, IcpOptions icp) {
  icp.metric = params.GetChoice<IcpMetric>("icp_metric", "point_to_point",
                                           {{"point_to_point", IcpMetric::kPointToPoint},
                                            {"point_to_plane", IcpMetric::kPointToPlane},
                                            {"generalized_pcl", IcpMetric::kGeneralizedPcl},
                                            {"stereo_rays", IcpMetric::kStereoRays}});
  icp.stereo.ray_sigma_coefficient =
      params.GetNonNegative("icp_ray_sigma_coefficient", icp.stereo.ray_sigma_coefficient);
  icp.stereo.plane_sigma = params.Get("icp_plane_sigma", icp.stereo.plane_sigma);
  params.Check(icp.stereo.plane_sigma > 0.0, "icp_plane_sigma", "must be > 0");
  icp.stereo.ray_reach = params.Get("icp_ray_reach", icp.stereo.ray_reach);
  params.Check(icp.stereo.ray_reach > 0.0, "icp_ray_reach", "must be > 0");
  icp.max_iterations = params.Get("max_iterations", icp.max_iterations);
  icp.max_correspondence_distance =
      params.Get("max_correspondence_distance", icp.max_correspondence_distance);
  icp.min_rms_improvement = params.Get("min_rms_improvement", icp.min_rms_improvement);
  icp.stop_on_rms_rise = params.Get("stop_on_rms_rise", icp.stop_on_rms_rise);
  icp.rms_epsilon = params.Get("rms_epsilon", icp.rms_epsilon);
  icp.independent_correspondences =
      params.Get("independent_correspondences", icp.independent_correspondences);
  return icp;
}

// The seed, the sensed cloud's bounds, tracking on or off and the registration gate.
void LoadSeedAndGate(aar_ros_common::ParamReader& params, RegistrarOptions& r) {
  r.seed = params.GetChoice<SeedMode>("seed", "centroid",
                                      {{"centroid", SeedMode::kCentroid},
                                       {"previous", SeedMode::kPrevious},
                                       {"prediction", SeedMode::kPrediction}});
  r.seed_points = aar_ros_common::LoadSeedPoints(params);
  r.previous_max_age = params.Get("previous_max_age", r.previous_max_age);
  r.max_sensed_points = params.Get("max_sensed_points", r.max_sensed_points);
  r.max_cloud_points = params.Get("max_cloud_points", r.max_cloud_points);
  params.Check(r.max_cloud_points >= 0, "max_cloud_points", "must be >= 0 (0: no bound)");
  r.subsample_seed =
      static_cast<unsigned>(params.Get("subsample_seed", static_cast<int>(r.subsample_seed)));
  r.track = params.Get("track", r.track);
  r.gate.min_fitness = params.Get("gate_min_fitness", r.gate.min_fitness);
  r.gate.max_rms = params.Get("gate_max_rms", r.gate.max_rms);
}

TrackerOptions LoadTrackerOptions(aar_ros_common::ParamReader& params, TrackerOptions t) {
  // Checked here under their YAML names (the tracker checks them again under its own).
  t.acceleration_sigma = params.GetPositive("acceleration_sigma", t.acceleration_sigma);
  t.angular_acceleration_sigma =
      params.GetPositive("angular_acceleration_sigma", t.angular_acceleration_sigma);
  t.initial_velocity_sigma = params.GetPositive("initial_velocity_sigma", t.initial_velocity_sigma);
  t.initial_angular_velocity_sigma =
      params.GetPositive("initial_angular_velocity_sigma", t.initial_angular_velocity_sigma);
  t.gate_chi2 = params.GetPositive("gate_chi2", t.gate_chi2);
  t.max_rejections = params.Get("max_rejections", t.max_rejections);
  params.Check(t.max_rejections >= 1, "max_rejections", "must be >= 1");
  t.max_coast_s = params.GetPositive("max_coast", t.max_coast_s);
  t.maneuver_acceleration_sigma =
      params.Get("maneuver_acceleration_sigma", t.maneuver_acceleration_sigma);
  params.Check(t.maneuver_acceleration_sigma >= 0.0, "maneuver_acceleration_sigma",
               "must be >= 0 (0: one model, no maneuvers)");
  t.maneuver_angular_acceleration_sigma = params.GetPositive("maneuver_angular_acceleration_sigma",
                                                             t.maneuver_angular_acceleration_sigma);
  t.steady_sojourn_s = params.GetPositive("steady_sojourn", t.steady_sojourn_s);
  t.maneuver_sojourn_s = params.GetPositive("maneuver_sojourn", t.maneuver_sojourn_s);
  return t;
}

// The start from the images (outline_image_start_*, outline_start_range_all): acquisition's
// options and the watch over a new track.
void LoadImageStartOptions(aar_ros_common::ParamReader& params, OutlineOptions& outline) {
  outline.image_start = params.Get("outline_image_start", outline.image_start);
  outline.image_start_quality =
      params.Get("outline_image_start_quality", outline.image_start_quality);
  aar_alignment::AcquisitionOptions& acquisition = outline.acquisition;
  acquisition.min_range = params.Get("outline_image_start_min_range", acquisition.min_range);
  acquisition.max_range = params.Get("outline_image_start_max_range", acquisition.max_range);
  acquisition.range_step = params.Get("outline_image_start_range_step", acquisition.range_step);
  acquisition.min_visible = params.Get("outline_image_start_min_visible", acquisition.min_visible);
  acquisition.both_views = params.Get("outline_image_start_both_views", acquisition.both_views);
  acquisition.cue_min_points =
      params.Get("outline_image_start_cue_min_points", acquisition.cue_min_points);
  acquisition.cue_margin_px =
      params.Get("outline_image_start_cue_margin", acquisition.cue_margin_px);
  acquisition.cue_disparity_margin_px =
      params.Get("outline_image_start_cue_disparity_margin", acquisition.cue_disparity_margin_px);
  outline.partial_below = params.Get("outline_image_start_partial_below", outline.partial_below);
  outline.partial_confirm =
      params.Get("outline_image_start_partial_confirm", outline.partial_confirm);
  outline.partial_range_sigmas =
      params.Get("outline_image_start_partial_range_sigmas", outline.partial_range_sigmas);
  outline.partial_range_min_points =
      params.Get("outline_image_start_partial_range_min_points", outline.partial_range_min_points);
  outline.partial_range_independent_points =
      params.Get("outline_image_start_partial_range_independent_points",
                 outline.partial_range_independent_points);
  outline.partial_range_required =
      params.Get("outline_image_start_partial_range_required", outline.partial_range_required);
  outline.range_all_starts = params.Get("outline_start_range_all", outline.range_all_starts);
  params.Check(outline.image_start_quality >= 0.0 && outline.image_start_quality <= 1.0,
               "outline_image_start_quality", "must lie in [0, 1]");
  params.Check(acquisition.min_range > 0.0, "outline_image_start_min_range", "must be > 0");
  params.Check(acquisition.max_range >= acquisition.min_range, "outline_image_start_max_range",
               "must be >= outline_image_start_min_range");
  params.Check(acquisition.range_step > 1.0, "outline_image_start_range_step", "must be > 1");
  params.Check(acquisition.min_visible >= 0.0 && acquisition.min_visible <= 1.0,
               "outline_image_start_min_visible", "must lie in [0, 1]");
  params.Check(outline.partial_below >= 0.0 && outline.partial_below <= 1.0,
               "outline_image_start_partial_below", "must lie in [0, 1]");
  params.Check(acquisition.cue_min_points >= 0, "outline_image_start_cue_min_points",
               "must be >= 0");
  params.Check(acquisition.cue_margin_px >= 0.0, "outline_image_start_cue_margin", "must be >= 0");
  params.Check(acquisition.cue_disparity_margin_px >= 0.0,
               "outline_image_start_cue_disparity_margin", "must be >= 0");
  params.Check(outline.partial_confirm >= 0, "outline_image_start_partial_confirm", "must be >= 0");
  params.Check(outline.partial_range_sigmas >= 0.0, "outline_image_start_partial_range_sigmas",
               "must be >= 0");
  params.Check(outline.partial_range_sigmas == 0.0 || outline.disparity_sigma > 0.0,
               "outline_image_start_partial_range_sigmas",
               "needs outline_disparity_sigma (stereo's noise) > 0");
  params.Check(!outline.range_all_starts || outline.partial_range_sigmas > 0.0,
               "outline_start_range_all", "needs outline_image_start_partial_range_sigmas > 0");
  params.Check(outline.partial_range_min_points >= 1,
               "outline_image_start_partial_range_min_points", "must be at least 1");
  params.Check(outline.partial_range_independent_points >= 1,
               "outline_image_start_partial_range_independent_points", "must be at least 1");
  params.Check(!outline.partial_range_required || outline.partial_range_sigmas > 0.0,
               "outline_image_start_partial_range_required",
               "needs outline_image_start_partial_range_sigmas > 0");
}

OutlineOptions LoadOutlineOptions(aar_ros_common::ParamReader& params, OutlineOptions outline) {
  outline.enabled = params.Get("outline", outline.enabled);
  outline.min_quality = params.Get("outline_min_quality", outline.min_quality);
  outline.max_poor_frames = params.Get("outline_max_poor_frames", outline.max_poor_frames);
  outline.start_candidates = params.Get("outline_start_candidates", outline.start_candidates);
  outline.maneuver_quality = params.Get("outline_maneuver_quality", outline.maneuver_quality);
  outline.start_sigma_position =
      params.Get("outline_start_sigma_position", outline.start_sigma_position);
  outline.start_sigma_rotation = aar_geometry::DegToRad(params.Get(
      "outline_start_sigma_rotation_deg", aar_geometry::RadToDeg(outline.start_sigma_rotation)));
  outline.disparity_sigma = params.Get("outline_disparity_sigma", outline.disparity_sigma);
  outline.disparity_rotation = params.Get("outline_disparity_rotation", outline.disparity_rotation);
  outline.remove_prior = params.Get("outline_remove_prior", outline.remove_prior);
  LoadImageStartOptions(params, outline);
  aar_alignment::AlignmentOptions& a = outline.alignment;
  a.contour_points = params.Get("outline_contour_points", a.contour_points);
  a.mask_size = params.Get("outline_mask_size", a.mask_size);
  a.mask_max_scale = params.GetPositive("outline_mask_max_scale", a.mask_max_scale);
  a.line_model =
      params.GetChoice<aar_alignment::LineModel>("outline_line_model", "contrast",
                                                 {{"contrast", aar_alignment::LineModel::kContrast},
                                                  {"region", aar_alignment::LineModel::kRegion}});
  a.search_radius_px = params.Get("outline_search_radius", a.search_radius_px);
  a.covariance_scale = params.Get("outline_covariance_scale", a.covariance_scale);
  a.rigs_share_errors = params.Get("outline_rigs_share_errors", a.rigs_share_errors);
  params.Check(outline.min_quality >= 0.0 && outline.min_quality <= 1.0, "outline_min_quality",
               "must lie in [0, 1]");
  params.Check(outline.maneuver_quality >= 0.0 && outline.maneuver_quality <= 1.0,
               "outline_maneuver_quality", "must lie in [0, 1]");
  params.Check(outline.max_poor_frames >= 1, "outline_max_poor_frames", "must be >= 1");
  params.Check(outline.start_candidates >= 1, "outline_start_candidates", "must be >= 1");
  params.Check(outline.start_sigma_position > 0.0, "outline_start_sigma_position", "must be > 0");
  params.Check(outline.start_sigma_rotation > 0.0, "outline_start_sigma_rotation_deg",
               "must be > 0");
  params.Check(outline.disparity_sigma >= 0.0, "outline_disparity_sigma", "must be >= 0");
  params.Check(!outline.image_start || outline.enabled, "outline_image_start",
               "needs outline: true");
  params.Check(a.contour_points >= 8, "outline_contour_points", "must be >= 8");
  params.Check(a.mask_size >= 32, "outline_mask_size", "must be >= 32 [px]");
  params.Check(a.search_radius_px >= 0.0, "outline_search_radius", "must be >= 0");
  params.Check(a.covariance_scale > 0.0, "outline_covariance_scale", "must be > 0");
  return outline;
}

// The alert bands: alert_band_max_range [m] (rising; the last band reaches any range beyond) and
// one more alert_limit_position [m], alert_limit_attitude_deg [deg] and alert_overbound_factor
// (0: integrity_overbound_factor) than ranges.
std::vector<AlertBand> LoadAlertBands(aar_ros_common::ParamReader& params,
                                      const std::vector<AlertBand>& defaults) {
  std::vector<double> ranges, positions, attitudes, factors;
  for (size_t i = 0; i < defaults.size(); ++i) {
    if (i + 1 < defaults.size()) ranges.push_back(defaults[i].max_range_m);
    positions.push_back(defaults[i].position_m);
    attitudes.push_back(defaults[i].attitude_deg);
    factors.push_back(defaults[i].overbound_factor);
  }
  ranges = params.Get("alert_band_max_range", ranges);
  positions = params.Get("alert_limit_position", positions);
  attitudes = params.Get("alert_limit_attitude_deg", attitudes);
  factors = params.Get("alert_overbound_factor", factors);
  params.Check(positions.size() == ranges.size() + 1, "alert_limit_position",
               "must hold one limit more than alert_band_max_range has ranges");
  params.Check(attitudes.size() == positions.size(), "alert_limit_attitude_deg",
               "must hold as many limits as alert_limit_position");
  params.Check(factors.size() == positions.size(), "alert_overbound_factor",
               "must hold as many factors as alert_limit_position has limits");
  std::vector<AlertBand> bands(positions.size());
  for (size_t i = 0; i < bands.size(); ++i) {
    if (i < ranges.size()) bands[i].max_range_m = ranges[i];
    bands[i].position_m = positions[i];
    bands[i].attitude_deg = attitudes[i];
    bands[i].overbound_factor = factors[i];
    params.Check(i == 0 || i == ranges.size() || ranges[i] > ranges[i - 1], "alert_band_max_range",
                 "must rise");
    params.Check(positions[i] > 0.0, "alert_limit_position", "must be > 0");
    params.Check(attitudes[i] > 0.0, "alert_limit_attitude_deg", "must be > 0");
    params.Check(factors[i] == 0.0 || factors[i] >= 1.0, "alert_overbound_factor",
                 "must be 0 (integrity_overbound_factor) or >= 1");
  }
  return bands;
}

IntegrityOptions LoadIntegrityOptions(aar_ros_common::ParamReader& params, IntegrityOptions o) {
  o.integrity_risk = params.GetPositive("integrity_risk", o.integrity_risk);
  params.Check(o.integrity_risk < 1.0, "integrity_risk", "must lie in (0, 1)");
  o.overbound_factor = params.Get("integrity_overbound_factor", o.overbound_factor);
  params.Check(o.overbound_factor >= 1.0, "integrity_overbound_factor", "must be >= 1");
  o.position_bias_m = params.GetNonNegative("integrity_position_bias", o.position_bias_m);
  o.attitude_bias_deg = params.GetNonNegative("integrity_attitude_bias_deg", o.attitude_bias_deg);
  o.confirm_frames = params.Get("integrity_confirm_frames", o.confirm_frames);
  params.Check(o.confirm_frames >= 0, "integrity_confirm_frames", "must be >= 0");
  o.attitude_envelope_deg =
      params.GetNonNegative("integrity_attitude_envelope_deg", o.attitude_envelope_deg);
  params.Check(o.attitude_envelope_deg < 180.0, "integrity_attitude_envelope_deg",
               "must be below 180");
  o.bands = LoadAlertBands(params, o.bands);
  return o;
}

void LoadRigs(aar_ros_common::ParamReader& params, RegistrationNodeOptions& o) {
  o.rigs = params.Get("rigs", o.rigs);
  params.Check(!o.rigs.empty(), "rigs", "must name at least one rig");
  std::set<std::string> seen;
  for (const std::string& rig : o.rigs) {
    params.Check(aar_ros_common::IsRigName(rig), "rigs",
                 "must hold rig names ([A-Za-z][A-Za-z0-9_]*), not '" + rig + "'");
    params.Check(seen.insert(rig).second, "rigs", "names '" + rig + "' twice");
  }
  o.rig_wait = params.GetNonNegative("rig_wait", o.rig_wait);
}

}  // namespace

RegistrationNodeOptions LoadRegistrationNodeOptions(const ros::NodeHandle& nh) {
  aar_ros_common::ParamReader params(nh);
  return LoadRegistrationNodeOptions(params);
}

RegistrationNodeOptions LoadRegistrationNodeOptions(aar_ros_common::ParamReader& params) {
  RegistrationNodeOptions o;
  RegistrarOptions& r = o.registrar;
  r.reference = params.GetChoice<ReferenceKind>("reference", "shelled",
                                                {{"shelled", ReferenceKind::kShelled},
                                                 {"wings_nose", ReferenceKind::kWingsNose},
                                                 {"dense", ReferenceKind::kDense},
                                                 {"topic", ReferenceKind::kTopic}});
  o.receiver = aar_ros_common::LoadReceiverModel(params, r.sampling);
  if (!o.receiver.static_parts.empty()) r.static_parts = o.receiver.static_parts;
  r.T_tanker_receiver_nominal = LoadNominalPose(params, o.receiver);
  r.icp = LoadIcpOptions(params, r.icp);
  LoadSeedAndGate(params, r);
  r.tracker = LoadTrackerOptions(params, r.tracker);
  r.outline = LoadOutlineOptions(params, r.outline);
  r.persistent_error.pixel_sigma =
      params.GetNonNegative("persistent_pixel_sigma", r.persistent_error.pixel_sigma);
  r.integrity = LoadIntegrityOptions(params, r.integrity);
  r.fault_start_offset_m = params.Get("fault_start_offset", r.fault_start_offset_m);
  o.common = aar_ros_common::LoadCommonNodeOptions(params, o.common);
  o.model_boom = params.Get("model_boom", o.model_boom);
  o.truth_frame = params.Get("truth_frame", o.truth_frame);
  o.newest_wins = params.Get("newest_wins", o.newest_wins);
  o.reference_timeout = params.GetNonNegative("reference_timeout", o.reference_timeout);
  o.max_stamp_lead = params.GetNonNegative("max_stamp_lead", o.max_stamp_lead);
  LoadRigs(params, o);

  params.RejectUnknown();
  // Rules across keys after the unknown ones: a misspelt `trak:` is named as such, not as
  // "outline needs track".
  params.Check(!r.outline.enabled || r.track, "outline", "needs track: true");
  // With more than one rig: the reference is each rig's own (the static shell is one rig's
  // view), and stereo_rays pairs along one left camera's rays.
  params.Check(o.rigs.size() == 1 || r.reference == ReferenceKind::kTopic, "rigs",
               "of more than one rig needs reference: topic (each rig's own reference)");
  params.Check(o.rigs.size() == 1 || r.icp.metric != IcpMetric::kStereoRays, "rigs",
               "of more than one rig cannot use icp_metric: stereo_rays (one camera's rays)");
  return o;
}

}  // namespace aar_registration
