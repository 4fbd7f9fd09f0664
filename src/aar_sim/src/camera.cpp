#include "aar_sim/camera.h"

#include <cmath>
#include <stdexcept>

#include <aar_geometry/pose.h>

namespace aar_sim {

CameraIntrinsics CameraIntrinsics::FromHorizontalFov(int width, int height, double hfov_deg) {
  if (width <= 0 || height <= 0 || !(hfov_deg > 0.0 && hfov_deg < 180.0)) {
    throw std::invalid_argument("camera needs a positive size and a field of view in (0, 180) deg");
  }
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width / std::tan(0.5 * aar_geometry::DegToRad(hfov_deg));
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

StereoRig MakeStereoRig(const CameraIntrinsics& intrinsics, double baseline,
                        const Eigen::Vector3d& centre_in_tanker, double yaw_deg,
                        double pitch_down_deg) {
  using aar_geometry::DegToRad;
  StereoRig rig;
  rig.intrinsics = intrinsics;
  rig.baseline = baseline;
  // Camera body frame (x along the view, REP-103: positive pitch is nose down), then optical.
  const Eigen::Isometry3d T_tanker_body = aar_geometry::MakeTransform(
      centre_in_tanker, {0.0, DegToRad(pitch_down_deg), DegToRad(yaw_deg)});
  const Eigen::Isometry3d T_tanker_centre_optical = T_tanker_body * aar_geometry::T_body_optical();
  rig.T_tanker_left_optical = T_tanker_centre_optical * Eigen::Translation3d(-0.5 * baseline, 0, 0);
  return rig;
}

}  // namespace aar_sim
