#include "aar_testing/alignment_views.h"

#include "aar_testing/sim_stereo.h"

namespace aar_testing {
namespace {

aar_alignment::PinholeCamera Camera(const aar_sim::StereoRig& rig,
                                    const Eigen::Isometry3d& T_tanker_optical) {
  aar_alignment::PinholeCamera c;
  c.width = rig.intrinsics.width, c.height = rig.intrinsics.height;
  c.fx = rig.intrinsics.fx, c.fy = rig.intrinsics.fy;
  c.cx = rig.intrinsics.cx, c.cy = rig.intrinsics.cy;
  c.T_tanker_optical = T_tanker_optical;
  return c;
}

}  // namespace

aar_alignment::PinholeCamera LeftCamera(const aar_sim::StereoRig& rig) {
  return Camera(rig, rig.T_tanker_left_optical);
}

aar_alignment::PinholeCamera RightCamera(const aar_sim::StereoRig& rig) {
  return Camera(rig, rig.T_tanker_right_optical());
}

aar_sim::WorldOptions RealisticWorld() {
  aar_sim::WorldOptions w = SimStereo::DefaultWorld();
  w.renderer.scene.background = aar_sim::Background::kTerrain;
  w.renderer.scene.cloud_coverage = 0.4;
  w.renderer.sun.enabled = true;
  w.propellers = aar_sim::PropellerMode::kBlades;
  w.sensor.noise_stddev = 2.0;
  w.sensor.full_well = 10000.0;
  w.sensor.gain_mismatch = 0.03;
  w.sensor.auto_exposure = true;
  return w;
}

}  // namespace aar_testing
