#pragma once

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <stereo_msgs/DisparityImage.h>

#include "aar_stereo/stereo.h"

namespace aar_stereo {

// The pair's geometry from its camera infos (P matrices). Throws std::invalid_argument naming the
// problem: a zero or non-finite P, sizes that differ, focal lengths that differ.
StereoGeometry ToStereoGeometry(const sensor_msgs::CameraInfo& left,
                                const sensor_msgs::CameraInfo& right);

// A view of a mono8 image (no copy). Throws std::invalid_argument for another encoding or a
// malformed step/size.
cv::Mat ToMono8(const sensor_msgs::Image& image, const char* which);

stereo_msgs::DisparityImagePtr ToDisparityMsg(const StereoResult& result,
                                              const StereoOptions& options,
                                              const StereoGeometry& geometry,
                                              const cv::Rect& valid_window,
                                              const std_msgs::Header& header);

// Fields x, y, z (float32) and, when present, intensity (float32).
sensor_msgs::PointCloud2Ptr ToPointCloud2Msg(const CloudPoints& cloud,
                                             const std_msgs::Header& header);

}  // namespace aar_stereo
