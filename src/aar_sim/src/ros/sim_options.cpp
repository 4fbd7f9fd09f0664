// The node's parameters, apart from the node so that they can be read without a master
// (ParamReader over a parameter tree: the parameter fuzz target).
#include <array>
#include <cmath>
#include <map>
#include <regex>
#include <set>
#include <string>

#include <aar_ros_common/param_reader.h>
#include <aar_ros_common/receiver_params.h>
#include <ros/package.h>

#include "aar_sim/ros/sim_node.h"

namespace aar_sim {
namespace {

// A list of `N` numbers under ~name (YAML [a, b, ...]), or `fallback` when unset.
template <size_t N>
std::array<double, N> GetNumbers(aar_ros_common::ParamReader& params, const std::string& name,
                                 const std::array<double, N>& fallback) {
  params.Allow(name);
  XmlRpc::XmlRpcValue value;
  if (!params.GetValue(name, value)) return fallback;
  const std::string rule = "must be a list of " + std::to_string(N) + " numbers";
  params.Check(value.getType() == XmlRpc::XmlRpcValue::TypeArray && value.size() == int(N), name,
               rule);
  std::array<double, N> out{};
  for (int i = 0; i < int(N); ++i) {
    XmlRpc::XmlRpcValue& x = value[i];
    if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
      out[size_t(i)] = static_cast<double>(x);
    } else if (x.getType() == XmlRpc::XmlRpcValue::TypeInt) {
      out[size_t(i)] = static_cast<int>(x);
    } else {
      params.Check(false, name, rule);
    }
    params.Check(std::isfinite(out[size_t(i)]), name, "must hold finite numbers");
  }
  return out;
}

LensOptions GetLens(aar_ros_common::ParamReader& params, const std::string& side,
                    const LensOptions& fallback) {
  LensOptions lens;
  lens.distortion = GetNumbers(params, side + "_distortion", fallback.distortion);
  const std::array<double, 3> r = GetNumbers<3>(
      params, side + "_rotation_deg",
      {fallback.rotation_deg.x(), fallback.rotation_deg.y(), fallback.rotation_deg.z()});
  lens.rotation_deg = {r[0], r[1], r[2]};
  params.Check(lens.rotation_deg.norm() <= 10.0, side + "_rotation_deg",
               "must stay within 10 deg of the rectified camera (a small mounting error)");
  return lens;
}

// The receiver, the boom and whether it is drawn.
void LoadModels(aar_ros_common::ParamReader& params, WorldOptions* world) {
  const std::string models = ros::package::getPath("aar_description") + "/models";
  world->receiver = aar_ros_common::LoadReceiver(params);
  world->boom_urdf = params.Get<std::string>("boom_urdf", models + "/boom.urdf");
  world->boom_visible = params.Get("boom", true);
}

// A rig's mount: the keys of config/mounts/*.yaml (a `rigs:` entry may set each of them).
const char* const kMountKeys[] = {"camera_x",       "camera_y",         "camera_z",
                                  "camera_yaw_deg", "camera_pitch_deg", "baseline"};
using Mount = std::map<std::string, double>;

// The world's cameras at `m`.
StereoRig RigAt(const CameraIntrinsics& cameras, Mount& m) {
  return MakeStereoRig(cameras, m["baseline"], {m["camera_x"], m["camera_y"], m["camera_z"]},
                       m["camera_yaw_deg"], m["camera_pitch_deg"]);
}

// The stereo rig: image size, field of view, baseline and mounting; its mount into *mount.
StereoRig LoadRig(aar_ros_common::ParamReader& params, Mount* mount) {
  const int width = params.Get("image_width", 1280);
  const int height = params.Get("image_height", 960);
  const double hfov = params.Get("hfov_deg", 60.0);
  const double defaults[] = {-20.0, 1.0, -3.0, 180.0, 25.0, 0.5};
  for (size_t i = 0; i < 6; ++i) (*mount)[kMountKeys[i]] = params.Get(kMountKeys[i], defaults[i]);
  params.Check(width > 0, "image_width", "must be positive");
  params.Check(height > 0, "image_height", "must be positive");
  params.Check(hfov > 0.0 && hfov < 180.0, "hfov_deg", "must be in (0, 180)");
  params.Check(mount->at("baseline") > 0.0, "baseline", "must be positive");
  return RigAt(CameraIntrinsics::FromHorizontalFov(width, height, hfov), *mount);
}

// One entry of ~rigs: its name and its mount (the top-level mount where it sets no key).
NamedRig LoadRigEntry(aar_ros_common::ParamReader& params, XmlRpc::XmlRpcValue& entry,
                      const StereoRig& first, Mount mount) {
  const std::string rule =
      "must be a list of {name: NAME, and any of camera_x, camera_y, camera_z, camera_yaw_deg, "
      "camera_pitch_deg, baseline}";
  params.Check(entry.getType() == XmlRpc::XmlRpcValue::TypeStruct && entry.hasMember("name") &&
                   entry["name"].getType() == XmlRpc::XmlRpcValue::TypeString,
               "rigs", rule);
  NamedRig out;
  out.name = static_cast<std::string>(entry["name"]);
  static const std::regex name_rule("[A-Za-z][A-Za-z0-9_]*");
  params.Check(std::regex_match(out.name, name_rule), "rigs",
               "names a rig '" + out.name + "': a name is a letter, then letters, digits or _");
  for (auto& [key, value] : entry) {
    if (key == "name") continue;
    params.Check(mount.count(key) == 1, "rigs", "rig " + out.name + ": unknown key " + key);
    const auto type = value.getType();
    params.Check(type == XmlRpc::XmlRpcValue::TypeDouble || type == XmlRpc::XmlRpcValue::TypeInt,
                 "rigs", "rig " + out.name + ": " + key + " must be a number");
    mount[key] =
        type == XmlRpc::XmlRpcValue::TypeInt ? static_cast<int>(value) : static_cast<double>(value);
    params.Check(std::isfinite(mount[key]), "rigs", "rig " + out.name + ": " + key + " not finite");
  }
  params.Check(mount["baseline"] > 0.0, "rigs", "rig " + out.name + ": baseline must be positive");
  out.rig = RigAt(first.intrinsics, mount);
  return out;
}

// ~rigs (absent: the one rig `stereo` of the top-level keys): the first must be `stereo` (its keys
// replace the top-level ones), the others are o->more_rigs.
void LoadRigs(aar_ros_common::ParamReader& params, const Mount& mount, SimNodeOptions* o) {
  params.Allow("rigs");
  XmlRpc::XmlRpcValue rigs;
  if (!params.GetValue("rigs", rigs)) return;
  params.Check(rigs.getType() == XmlRpc::XmlRpcValue::TypeArray && rigs.size() >= 1, "rigs",
               "must be a list of rigs, the first named stereo");
  std::set<std::string> names;
  for (int i = 0; i < rigs.size(); ++i) {
    NamedRig rig = LoadRigEntry(params, rigs[i], o->world.rig, mount);
    params.Check(names.insert(rig.name).second, "rigs", "names rig " + rig.name + " twice");
    params.Check((i == 0) == (rig.name == "stereo"), "rigs",
                 "the first rig is stereo (today's topics and frames), and only the first");
    if (i == 0) {
      o->world.rig = rig.rig;
    } else {
      o->more_rigs.push_back(rig);
    }
  }
}

// Raw cameras: distorted, unrectified images with their calibration (off: rectified pinhole).
void LoadRawCameras(aar_ros_common::ParamReader& params, RawCameraOptions* raw) {
  const RawCameraOptions raw_defaults = DefaultRawCameraOptions();
  raw->enabled = params.Get("raw_images", false);
  raw->left = GetLens(params, "left", raw_defaults.left);
  raw->right = GetLens(params, "right", raw_defaults.right);
}

// The read noise and the plain sky's grey level.
void LoadNoiseAndSky(aar_ros_common::ParamReader& params, WorldOptions* world) {
  world->sensor.noise_stddev = params.Get("noise_stddev", 0.0);
  world->sensor.noise_seed = static_cast<uint64_t>(params.Get("noise_seed", 1));
  world->renderer.sky_level = params.Get("sky_level", 200.0);
  params.Check(world->sensor.noise_stddev >= 0.0, "noise_stddev", "must not be negative");
}

// The node's loop: rate, time span, lockstep, what it publishes and how it stamps it.
void LoadLoop(aar_ros_common::ParamReader& params, SimNodeOptions* o) {
  o->rate = params.Get("rate", o->rate);
  o->start_time = params.Get("start_time", o->start_time);
  o->max_frames = params.Get("frames", o->max_frames);
  o->lockstep = params.Get("lockstep", o->lockstep);
  o->lockstep_timeout = params.Get("lockstep_timeout", o->lockstep_timeout);
  o->estimate_publisher = params.Get("estimate_publisher", o->estimate_publisher);
  o->realtime_factor = params.Get("realtime_factor", o->realtime_factor);
  o->wait_for_subscribers = params.Get("wait_for_subscribers", o->lockstep);
  o->start_delay = params.Get("start_delay", o->start_delay);
  params.Check(o->start_delay >= 0.0, "start_delay", "must not be negative");
  o->publish_labels = params.Get("publish_labels", o->publish_labels);
  o->measure_visibility = params.Get("measure_visibility", o->lockstep);
  o->shutdown_at_end = params.Get("shutdown_at_end", o->shutdown_at_end);
  o->stamp_offset = params.Get("stamp_offset", o->stamp_offset);
  params.Check(o->rate > 0.0, "rate", "must be positive");
  params.Check(o->max_frames >= 0, "frames", "must not be negative");
  params.Check(o->lockstep_timeout > 0.0, "lockstep_timeout", "must be positive");
  params.Check(o->realtime_factor > 0.0 && o->realtime_factor <= 100.0, "realtime_factor",
               "must be above 0 and at most 100");
  params.Check(o->stamp_offset > 0.0, "stamp_offset", "must be positive");
}

// Scene: background (issue 16, docs/realism/scene.md).
void LoadScene(aar_ros_common::ParamReader& params, SceneOptions* scene) {
  SceneOptions& sc = *scene;
  const std::string background = params.Get<std::string>("background", "none");
  params.Check(background == "none" || background == "sea" || background == "terrain", "background",
               "must be none, sea or terrain");
  sc.background = background == "sea"       ? Background::kSea
                  : background == "terrain" ? Background::kTerrain
                                            : Background::kNone;
  sc.background_altitude_m = params.Get("background_altitude", sc.background_altitude_m);
  sc.visibility_m = params.Get("visibility", sc.visibility_m);
  sc.cloud_coverage = params.Get("cloud_coverage", sc.cloud_coverage);
  sc.cloud_altitude_m = params.Get("cloud_altitude", sc.cloud_altitude_m);
  sc.cloud_min_range_m = params.Get("cloud_min_range", sc.cloud_min_range_m);
  params.Check(sc.background_altitude_m > 0.0, "background_altitude", "must be positive");
  params.Check(sc.visibility_m > 0.0, "visibility", "must be positive");
  params.Check(sc.cloud_coverage >= 0.0 && sc.cloud_coverage <= 1.0, "cloud_coverage",
               "must be in [0, 1]");
  params.Check(sc.cloud_altitude_m > 0.0 && sc.cloud_altitude_m < sc.background_altitude_m,
               "cloud_altitude", "must be positive and below background_altitude");
  params.Check(sc.cloud_min_range_m >= 0.0, "cloud_min_range", "must not be negative");
}

// The sun (docs/realism/sun.md): off by default (the thesis's fixed light).
void LoadSun(aar_ros_common::ParamReader& params, SunOptions* sun_options) {
  SunOptions& sun = *sun_options;
  sun.enabled = params.Get("sun", sun.enabled);
  sun.azimuth_deg = params.Get("sun_azimuth_deg", sun.azimuth_deg);
  sun.elevation_deg = params.Get("sun_elevation_deg", sun.elevation_deg);
  sun.direct = params.Get("sun_direct", sun.direct);
  sun.ambient = params.Get("sun_ambient", sun.ambient);
  sun.shadows = params.Get("sun_shadows", sun.shadows);
  sun.shadow_map_size = params.Get("sun_shadow_map_size", sun.shadow_map_size);
  sun.paint_specular = params.Get("sun_paint_specular", sun.paint_specular);
  sun.metal_specular = params.Get("sun_metal_specular", sun.metal_specular);
  sun.glass_specular = params.Get("sun_glass_specular", sun.glass_specular);
  params.Check(sun.elevation_deg > 0.0 && sun.elevation_deg <= 90.0, "sun_elevation_deg",
               "must be in (0, 90] deg: a sun at or below the horizon lights nothing from above");
  params.Check(std::isfinite(sun.azimuth_deg), "sun_azimuth_deg", "must be a finite angle");
  params.Check(sun.direct > 0.0 && sun.direct <= 4.0, "sun_direct", "must be in (0, 4]");
  params.Check(sun.ambient >= 0.0 && sun.ambient <= 2.0, "sun_ambient", "must be in [0, 2]");
  params.Check(sun.shadow_map_size >= 64 && sun.shadow_map_size <= 8192, "sun_shadow_map_size",
               "must be from 64 to 8192 texels");
  params.Check(sun.paint_specular >= 0.0, "sun_paint_specular", "must not be negative");
  params.Check(sun.metal_specular >= 0.0, "sun_metal_specular", "must not be negative");
  params.Check(sun.glass_specular >= 0.0, "sun_glass_specular", "must not be negative");
}

// The propellers (docs/realism/sun.md): none by default.
PropellerMode LoadPropellerMode(aar_ros_common::ParamReader& params) {
  return params.GetChoice<PropellerMode>("propellers", "none",
                                         {{"none", PropellerMode::kNone},
                                          {"blades", PropellerMode::kBlades},
                                          {"disc", PropellerMode::kDisc}});
}

// Turbulence (docs/realism/turbulence.md): Dryden gusts moving the receiver and the boom.
void LoadTurbulence(aar_ros_common::ParamReader& params, TurbulenceOptions* turbulence) {
  turbulence->intensity =
      params.GetChoice<TurbulenceIntensity>("turbulence", "none",
                                            {{"none", TurbulenceIntensity::kNone},
                                             {"light", TurbulenceIntensity::kLight},
                                             {"moderate", TurbulenceIntensity::kModerate},
                                             {"severe", TurbulenceIntensity::kSevere}});
  const int turbulence_seed = params.Get("turbulence_seed", 1);
  params.Check(turbulence_seed >= 0, "turbulence_seed", "must not be negative");
  turbulence->seed = static_cast<uint64_t>(turbulence_seed);
  turbulence->airspeed = params.Get("turbulence_airspeed", turbulence->airspeed);
  params.Check(turbulence->airspeed > 0.0, "turbulence_airspeed", "must be positive [m/s]");
  turbulence->altitude = params.Get("turbulence_altitude", turbulence->altitude);
  params.Check(turbulence->altitude >= 2000 * kFoot && turbulence->altitude <= 80000 * kFoot,
               "turbulence_altitude",
               "must be from 609.6 to 24384 m (2000 to 80000 ft: the medium/high-altitude model)");
}

// Sensor (config/sim.yaml "# Sensor", docs/realism/sensor.md): each effect off by default;
// noise_stddev and noise_seed (LoadNoiseAndSky) are its read noise.
void LoadSensor(aar_ros_common::ParamReader& params, SensorOptions* sensor_options) {
  SensorOptions& sensor = *sensor_options;
  sensor.full_well = params.Get("full_well", sensor.full_well);
  sensor.motion_blur = params.Get("motion_blur", sensor.motion_blur);
  sensor.exposure_time = params.Get("exposure_time", sensor.exposure_time);
  sensor.gain_mismatch = params.Get("gain_mismatch", sensor.gain_mismatch);
  sensor.auto_exposure = params.Get("auto_exposure", sensor.auto_exposure);
  sensor.exposure_target = params.Get("exposure_target", sensor.exposure_target);
  sensor.exposure_gain_min = params.Get("exposure_gain_min", sensor.exposure_gain_min);
  sensor.exposure_gain_max = params.Get("exposure_gain_max", sensor.exposure_gain_max);
  params.Check(sensor.full_well >= 0.0, "full_well",
               "must not be negative (electrons of a full pixel; 0: no shot noise)");
  params.Check(sensor.exposure_time > 0.0, "exposure_time",
               "must be positive: an exposure of zero (or less) collects no light");
  params.Check(sensor.exposure_time <= 1.0, "exposure_time",
               "must be at most 1 s (one frame of a 1 Hz camera)");
  params.Check(std::abs(sensor.gain_mismatch) < 0.5, "gain_mismatch",
               "must be within (-0.5, 0.5): the right camera's gain over the left's, minus 1");
  params.Check(sensor.exposure_target > 0.0 && sensor.exposure_target < 255.0, "exposure_target",
               "must be in (0, 255) grey levels");
  params.Check(sensor.exposure_gain_min > 0.0, "exposure_gain_min", "must be positive");
  params.Check(sensor.exposure_gain_max >= sensor.exposure_gain_min, "exposure_gain_max",
               "must not be below exposure_gain_min");
}

}  // namespace

SimNodeOptions LoadSimNodeOptions(const ros::NodeHandle& nh) {
  aar_ros_common::ParamReader params(nh);
  return LoadSimNodeOptions(params);
}

// Option group by option group, in the order their parameters have always been read and checked
// (the first bad one is the error).
SimNodeOptions LoadSimNodeOptions(aar_ros_common::ParamReader& params) {
  SimNodeOptions o;
  params.Allow("robot_description");  // tolerated: some launch files put it here
  o.flight_path = params.Required("flight_path", "a flight-path CSV");
  LoadModels(params, &o.world);
  Mount mount;
  o.world.rig = LoadRig(params, &mount);
  LoadRigs(params, mount, &o);
  LoadRawCameras(params, &o.world.raw);
  LoadNoiseAndSky(params, &o.world);
  LoadLoop(params, &o);
  LoadScene(params, &o.world.renderer.scene);
  LoadSun(params, &o.world.renderer.sun);
  o.world.propellers = LoadPropellerMode(params);
  LoadTurbulence(params, &o.turbulence);
  LoadSensor(params, &o.world.sensor);
  params.RejectUnknown();
  return o;
}

}  // namespace aar_sim
