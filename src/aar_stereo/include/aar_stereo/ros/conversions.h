#pragma once

#include <string>

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <stereo_msgs/DisparityImage.h>

#include "aar_stereo/stereo.h"

namespace aar_stereo {

// The pair's rectified geometry from its camera infos, through image_geometry's
// StereoCameraModel (P, with binning and region of interest applied as image_geometry does).
// Throws std::invalid_argument naming the problem and the topic (`left_topic`, `right_topic`): a
// zero or non-finite P, a D whose length does not fit the distortion model, sizes that differ,
// focal lengths that differ, a right P without a baseline.
StereoGeometry ToStereoGeometry(const sensor_msgs::CameraInfo& left,
                                const sensor_msgs::CameraInfo& right,
                                const std::string& left_topic = "left",
                                const std::string& right_topic = "right");

// The D length a distortion model takes (plumb_bob 5, rational_polynomial 8, equidistant 4), or
// -1 for a model image_geometry does not know.
int DistortionLength(const std::string& model);

// "" when the camera info has no distortion (D all zero or empty), else its D, e.g.
// "plumb_bob D = [-0.26, 0.09, 0.0006, -0.0004, -0.012]".
std::string DescribeDistortion(const sensor_msgs::CameraInfo& info);

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
