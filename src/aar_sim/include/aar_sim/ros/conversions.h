#pragma once

#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "aar_sim/camera.h"
#include "aar_sim/raw_camera.h"
#include "aar_sim/renderer.h"

namespace aar_sim {

sensor_msgs::ImagePtr ToImageMsg(const Image<uint8_t>& image, const std_msgs::Header& header);

// Rectified pinhole camera info. `Tx` is P[0][3] = -fx * baseline for the right camera of a
// stereo pair and 0 for the left (stereo_image_proc's convention).
sensor_msgs::CameraInfoPtr ToCameraInfoMsg(const CameraIntrinsics& k, double Tx,
                                           const std_msgs::Header& header);

// A raw camera's info as camera_calibration writes it: D (plumb_bob), K (the raw intrinsics),
// R (raw camera into the rectified one) and P, the rectified projection (`rectified`, with Tx).
sensor_msgs::CameraInfoPtr ToRawCameraInfoMsg(const RawCamera& camera,
                                              const CameraIntrinsics& rectified, double Tx,
                                              const std_msgs::Header& header);

geometry_msgs::TransformStamped ToTransformMsg(const Eigen::Isometry3d& T_parent_child,
                                               const ros::Time& stamp, const std::string& parent,
                                               const std::string& child);

}  // namespace aar_sim
