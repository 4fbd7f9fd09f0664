#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "aar_sim/camera.h"
#include "aar_sim/renderer.h"

namespace aar_sim {

// The camera's sensor: how the radiance reaching a pixel during the exposure becomes its grey
// level (docs/realism/sensor.md). The defaults are the ideal camera of the thesis: grey =
// round(255 r) clipped to 0..255, exactly as OpenGL's conversion to an 8-bit attachment rounds.
struct SensorOptions {
  double noise_stddev = 0.0;     // [grey levels] Gaussian read noise; 0 = none
  uint64_t noise_seed = 1;       // noise of view k (2 frame + camera) depends only on (seed, k)
  double full_well = 0.0;        // [e-] electrons at grey 255: shot noise (Poisson); 0 = none
  bool motion_blur = false;      // average the radiance along each pixel's motion in the exposure
  double exposure_time = 0.002;  // [s] > 0: the interval motion blur integrates over
  double gain_mismatch = 0.0;    // the right camera's gain over the left's, minus 1 (0.03: +3 %)
  bool auto_exposure = false;  // scale the signal so that the metered radiance lands on the target
  double exposure_target = 118.0;   // [grey level] of the metered mean (0 < target < 255)
  double exposure_gain_min = 0.25;  // auto-exposure's limits on its scale factor
  double exposure_gain_max = 4.0;

  // Throws std::invalid_argument naming the field that is out of range.
  void Validate() const;
};

// A rigid body's motion during the exposure as one camera sees it.
struct BodyMotion {
  // A point of the body in the optical frame at the exposure's start -> at its end.
  Eigen::Isometry3d T_end_start = Eigen::Isometry3d::Identity();
  // Where the body is: its box in its own frame, and that frame from the optical one (at the
  // start). Several bodies of one label (the boom's links): a pixel moves with the nearest box.
  Eigen::Isometry3d T_body_optical = Eigen::Isometry3d::Identity();
  Eigen::AlignedBox3d box_in_body;
};

// How the scene moves during one view's exposure; labels without a body stay still.
struct ViewMotion {
  CameraIntrinsics intrinsics;  // of the rendered view
  std::vector<std::pair<Label, BodyMotion>> bodies;
};

// One view as the sensor gets it.
struct SensorInput {
  const Image<float>* radiance = nullptr;  // required
  const Image<uint8_t>* label = nullptr;   // motion blur: required
  const Image<float>* depth = nullptr;     // motion blur: required [m] optical z, 0 background
  const ViewMotion* motion = nullptr;      // null: nothing moves (no blur)
  int camera = 0;                          // 0 left, 1 right (gain_mismatch)
  uint64_t view_key = 0;                   // 2 frame + camera: selects the noise streams
  double exposure_gain = 1.0;              // ExposureGain of the pair (the same for both)
};

// The auto-exposure's scale factor for a pair, metered on one view's radiance (the left: a
// synchronised rig meters once): 1 when auto_exposure is off. The mean over the central half of
// each axis, clipped at white, lands on exposure_target, unless more than 1 % of those pixels
// would clip or the limits stop it.
double ExposureGain(const SensorOptions& options, const Image<float>& radiance);

// The radiance averaged along each pixel's image motion over the exposure (motion blur).
Image<float> MotionBlur(const Image<float>& radiance, const Image<uint8_t>& label,
                        const Image<float>& depth, const ViewMotion& motion);

// The view's mono8 image: motion blur (when on and given motion), gain, shot noise, quantisation,
// read noise. Deterministic: the same input and key give the same bits.
Image<uint8_t> Expose(const SensorOptions& options, const SensorInput& input);

// OpenGL's float to 8-bit unsigned normalised conversion as Mesa's llvmpipe does it (ties to
// even): round(clamp(r, 0, 1) * 255).
uint8_t ToUnorm8(float r);

}  // namespace aar_sim
