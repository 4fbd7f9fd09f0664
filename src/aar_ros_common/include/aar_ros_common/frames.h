#pragma once

#include <string>

#include "aar_ros_common/param_reader.h"

namespace aar_ros_common {

// The tf frames the perception nodes share, with the stack's names (docs/ARCHITECTURE.md, Frames).
struct StackFrames {
  std::string tanker = "tanker";
  std::string receiver = "receiver";  // the estimate: tf tanker -> receiver
  std::string left_camera = "stereo_left_optical";
  std::string right_camera = "stereo_right_optical";
};

// ~tanker_frame, ~receiver_frame, ~left_camera_frame, ~right_camera_frame over `defaults`.
inline StackFrames LoadStackFrames(ParamReader& params, const StackFrames& defaults = {}) {
  StackFrames f = defaults;
  f.tanker = params.Get("tanker_frame", f.tanker);
  f.receiver = params.Get("receiver_frame", f.receiver);
  f.left_camera = params.Get("left_camera_frame", f.left_camera);
  f.right_camera = params.Get("right_camera_frame", f.right_camera);
  return f;
}

}  // namespace aar_ros_common
