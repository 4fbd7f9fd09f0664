#include "aar_stereo/ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <image_geometry/stereo_camera_model.h>
#include <sensor_msgs/distortion_models.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <boost/make_shared.hpp>

namespace aar_stereo {

int DistortionLength(const std::string& model) {
  if (model == sensor_msgs::distortion_models::PLUMB_BOB) return 5;
  if (model == sensor_msgs::distortion_models::RATIONAL_POLYNOMIAL) return 8;
  if (model == sensor_msgs::distortion_models::EQUIDISTANT) return 4;
  return -1;
}

std::string DescribeDistortion(const sensor_msgs::CameraInfo& info) {
  if (std::all_of(info.D.begin(), info.D.end(), [](double d) { return d == 0.0; })) return "";
  std::ostringstream s;
  s << info.distortion_model << " D = [";
  for (size_t i = 0; i < info.D.size(); ++i) s << (i ? ", " : "") << info.D[i];
  s << "]";
  return s.str();
}

StereoGeometry ToStereoGeometry(const sensor_msgs::CameraInfo& left,
                                const sensor_msgs::CameraInfo& right, const std::string& left_topic,
                                const std::string& right_topic) {
  // image_geometry asserts (aborts) or divides by zero on what is checked here: checked first.
  for (const auto* info : {&left, &right}) {
    const std::string which = (info == &left ? "left" : "right") + std::string(" camera info (") +
                              (info == &left ? left_topic : right_topic) + ")";
    for (double p : info->P) {
      if (!std::isfinite(p)) throw std::invalid_argument(which + " P is not finite");
    }
    if (info->P[0] <= 0.0 || info->P[5] <= 0.0 || info->P[10] != 1.0) {
      throw std::invalid_argument(
          which +
          " has no valid projection matrix P (zero focal length? fx, fy must be positive, "
          "P[10] = 1): is the camera rectified and calibrated?");
    }
    // An empty D means no distortion whatever the model says (an uncalibrated driver's info).
    const int expected = DistortionLength(info->distortion_model);
    if (!info->D.empty() && expected < 0) {
      throw std::invalid_argument(which + " has distortion model '" + info->distortion_model +
                                  "' with " + std::to_string(info->D.size()) +
                                  " coefficients: image_geometry knows plumb_bob, "
                                  "rational_polynomial and equidistant");
    }
    if (!info->D.empty() && static_cast<int>(info->D.size()) != expected) {
      throw std::invalid_argument(which + " has " + std::to_string(info->D.size()) +
                                  " distortion coefficients D; model " + info->distortion_model +
                                  " takes " + std::to_string(expected));
    }
  }
  if (left.width != right.width || left.height != right.height) {
    throw std::invalid_argument("camera infos differ in size: left (" + left_topic + ") " +
                                std::to_string(left.width) + "x" + std::to_string(left.height) +
                                ", right (" + right_topic + ") " + std::to_string(right.width) +
                                "x" + std::to_string(right.height));
  }
  // image_geometry scales P by binning and shifts it by the region of interest, then asserts
  // that the two cameras' fx, fy and cy agree: a pair binned or cropped differently aborted it.
  const auto bins = [](uint32_t b) { return b > 1 ? b : 1u; };  // 0 and 1: no binning
  if (bins(left.binning_x) != bins(right.binning_x) ||
      bins(left.binning_y) != bins(right.binning_y) || left.roi.y_offset != right.roi.y_offset) {
    throw std::invalid_argument("left (" + left_topic + ") and right (" + right_topic +
                                ") camera infos differ in binning or in their region of "
                                "interest's row offset: not a rectified pair");
  }
  if (left.P[0] != right.P[0] || left.P[5] != right.P[5] || left.P[6] != right.P[6]) {
    throw std::invalid_argument("left (" + left_topic + ") and right (" + right_topic +
                                ") camera infos differ in fx, fy or cy: not a rectified pair");
  }
  if (right.P[3] == 0.0) {
    throw std::invalid_argument("right camera info (" + right_topic +
                                ") P has no baseline (P[3] = Tx = 0; it must be -fx * baseline): "
                                "is it the left camera's info, or an uncalibrated pair?");
  }
  // image_geometry asserts that both infos name one frame (ROS's stereo convention, which the
  // right camera's P follows); only the geometry is taken here, so the frames are made equal.
  sensor_msgs::CameraInfo right_in_left = right;
  right_in_left.header.frame_id = left.header.frame_id;
  image_geometry::StereoCameraModel model;
  model.fromCameraInfo(left, right_in_left);
  const image_geometry::PinholeCameraModel &l = model.left(), &r = model.right();
  StereoGeometry g;
  g.width = static_cast<int>(left.width);
  g.height = static_cast<int>(left.height);
  g.fx = l.fx();
  g.fy = l.fy();
  g.cx_left = l.cx();
  g.cy = l.cy();
  g.cx_right = r.cx();
  g.Tx = r.Tx();
  g.Validate();
  return g;
}

cv::Mat ToMono8(const sensor_msgs::Image& image, const char* which) {
  if (image.encoding != sensor_msgs::image_encodings::MONO8) {
    throw std::invalid_argument(std::string(which) + " image has encoding '" + image.encoding +
                                "'; aar_stereo needs mono8 rectified images");
  }
  if (image.width == 0 || image.height == 0 || image.step < image.width ||
      image.data.size() < static_cast<size_t>(image.step) * image.height) {
    throw std::invalid_argument(std::string(which) + " image is malformed (size " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) +
                                ", step " + std::to_string(image.step) + ", " +
                                std::to_string(image.data.size()) + " bytes)");
  }
  return cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC1,
                 const_cast<uint8_t*>(image.data.data()), image.step);
}

stereo_msgs::DisparityImagePtr ToDisparityMsg(const StereoResult& result,
                                              const StereoOptions& options,
                                              const StereoGeometry& geometry,
                                              const cv::Rect& valid_window,
                                              const std_msgs::Header& header) {
  auto msg = boost::make_shared<stereo_msgs::DisparityImage>();
  msg->header = header;
  sensor_msgs::Image& image = msg->image;
  image.header = header;
  image.height = result.disparity.rows;
  image.width = result.disparity.cols;
  image.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  image.step = image.width * sizeof(float);
  image.data.resize(static_cast<size_t>(image.step) * image.height);
  for (int v = 0; v < result.disparity.rows; ++v) {
    std::memcpy(&image.data[static_cast<size_t>(v) * image.step], result.disparity.ptr<float>(v),
                image.step);
  }
  msg->f = static_cast<float>(geometry.fx);
  msg->T = static_cast<float>(geometry.baseline());
  msg->valid_window.x_offset = valid_window.x;
  msg->valid_window.y_offset = valid_window.y;
  msg->valid_window.width = valid_window.width;
  msg->valid_window.height = valid_window.height;
  msg->min_disparity = static_cast<float>(options.min_disparity);
  msg->max_disparity = static_cast<float>(options.min_disparity + options.num_disparities - 1);
  msg->delta_d = 1.0f / 16.0f;
  return msg;
}

sensor_msgs::PointCloud2Ptr ToPointCloud2Msg(const CloudPoints& cloud,
                                             const std_msgs::Header& header) {
  auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
  msg->header = header;
  sensor_msgs::PointCloud2Modifier modifier(*msg);
  const bool intensity = !cloud.intensity.empty();
  if (intensity) {
    modifier.setPointCloud2Fields(
        4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z",
        1, sensor_msgs::PointField::FLOAT32, "intensity", 1, sensor_msgs::PointField::FLOAT32);
  } else {
    modifier.setPointCloud2FieldsByString(1, "xyz");
  }
  modifier.resize(cloud.xyz.size());
  msg->width = static_cast<uint32_t>(cloud.width);
  msg->height = static_cast<uint32_t>(cloud.height);
  msg->row_step = msg->width * msg->point_step;
  msg->is_dense = cloud.height == 1;  // organized clouds carry NaN for invalid pixels
  // sensor_msgs' iterators start at data.front(): undefined behaviour on an empty cloud (a frame
  // without a valid disparity; found by the stereo_input fuzz target).
  if (cloud.xyz.empty()) return msg;
  sensor_msgs::PointCloud2Iterator<float> x(*msg, "x"), y(*msg, "y"), z(*msg, "z");
  for (size_t i = 0; i < cloud.xyz.size(); ++i, ++x, ++y, ++z) {
    *x = cloud.xyz[i].x();
    *y = cloud.xyz[i].y();
    *z = cloud.xyz[i].z();
  }
  if (intensity) {
    sensor_msgs::PointCloud2Iterator<float> in(*msg, "intensity");
    for (size_t i = 0; i < cloud.intensity.size(); ++i, ++in) *in = cloud.intensity[i];
  }
  return msg;
}

}  // namespace aar_stereo
