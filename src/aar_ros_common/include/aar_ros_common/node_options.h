#pragma once

#include <string>

#include "aar_ros_common/frames.h"
#include "aar_ros_common/param_reader.h"

namespace aar_ros_common {

// What the perception nodes (stereo, occlusion, registration) share: their frames, where the
// boom's URDF is, how long they wait for tf, how often they report, and how old an estimate they
// still use. Each node passes its own defaults; LoadCommonNodeOptions reads the keys over them.
struct CommonNodeOptions {
  StackFrames frames;                                   // tanker, receiver (estimate), cameras
  std::string robot_description = "robot_description";  // parameter holding the boom's URDF
  double tf_timeout = 0.5;                              // [s wall] waiting for a stamp's tf
  // [s] > 0: when tf has nothing at a stamp after tf_timeout, the latest transform at most this
  // much older (the boom's joints a frame old rather than a wait for their tf; real time). 0: off.
  double tf_fallback_age = 0.0;
  double diagnostic_period = 1.0;  // [s wall] /diagnostics
  // [s] an older estimate is not used as the predicted pose. 0: the node reads no estimate
  // (registration makes it), and ~estimate_max_age is not one of its keys.
  double estimate_max_age = 0.0;
  // The stereo rig a stage before registration serves when there are several (issue 44): its
  // namespace, e.g. share_mirror; its frame ledger reports RIG/stereo, RIG/occlusion, whose drops
  // do not settle the frame (registration answers from the other rigs). Empty: the first rig.
  std::string rig;
};

// A rig's name as a namespace and frame prefix takes: [A-Za-z][A-Za-z0-9_]*.
bool IsRigName(const std::string& name);

// ~tanker_frame, ~receiver_frame, ~left_camera_frame, ~right_camera_frame, ~robot_description,
// ~tf_timeout, ~tf_fallback_age, ~diagnostic_period and (when defaults.estimate_max_age > 0)
// ~estimate_max_age and ~rig (the stages that read an estimate: those before registration), each
// over `defaults`. Throws std::invalid_argument naming the key.
CommonNodeOptions LoadCommonNodeOptions(ParamReader& params, const CommonNodeOptions& defaults);

}  // namespace aar_ros_common
