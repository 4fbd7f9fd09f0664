// Fuzz target stereo_input: what the stereo node receives per frame, deserialized from the bytes
// as roscpp hands them over: the left and right sensor_msgs/CameraInfo, then the left and right
// sensor_msgs/Image. Then the node's frame: aar_stereo::ToStereoGeometry, ToMono8, matching
// (whole image and a region of interest, aar_stereo::ProjectedRoi), ToDisparityMsg and
// ToPointCloud2Msg. Conversions and matching may refuse their input with std::invalid_argument.
#include <optional>
#include <stdexcept>

#include <aar_ros_common/point_cloud.h>
#include <aar_stereo/ros/conversions.h>
#include <aar_stereo/stereo.h>

#include "fuzz_support.h"

namespace {

using aar_stereo::StereoGeometry;

// A receiver-sized box 40 m ahead of the left camera: the region the node would match.
std::vector<Eigen::Vector3d> PredictedReceiver() {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-10.0, -3.0, -8.0),
                                Eigen::Vector3d(10.0, 3.0, 8.0));
  return aar_stereo::BoxCorners(box, Eigen::Isometry3d(Eigen::Translation3d(0.0, 2.0, 40.0)), 2.0);
}

void Match(const aar_stereo::StereoProcessor& processor, const cv::Mat& left, const cv::Mat& right,
           const StereoGeometry& geometry, const std::optional<cv::Rect>& roi,
           const std_msgs::Header& header) {
  aar_stereo::StereoResult result;
  try {
    result = processor.Process(left, right, geometry, roi);
  } catch (const std::invalid_argument&) {
    return;  // images of another size than the camera infos'
  }
  FUZZ_CHECK(result.disparity.rows == left.rows && result.disparity.cols == left.cols,
             "a disparity per pixel");
  const auto disparity = aar_stereo::ToDisparityMsg(result, processor.options(), geometry,
                                                    result.valid_window, header);
  FUZZ_CHECK(disparity->image.data.size() == disparity->image.step * disparity->image.height,
             "the disparity image holds its pixels");
  const auto cloud = aar_stereo::ToPointCloud2Msg(result.cloud, header);
  const aar_ros_common::CloudPoints points = aar_ros_common::FromCloud(*cloud);  // reads back
  size_t finite = 0;
  for (const auto& p : result.cloud.xyz) finite += p.allFinite();
  FUZZ_CHECK(points.points.size() == finite, "the published cloud holds the finite points");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ros::serialization::IStream stream(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
  sensor_msgs::CameraInfo left_info, right_info;
  if (!aar_fuzz::NextMessage<sensor_msgs::CameraInfo_>(stream, left_info) ||
      !aar_fuzz::NextMessage<sensor_msgs::CameraInfo_>(stream, right_info))
    return 0;
  std::optional<StereoGeometry> geometry;
  try {
    geometry = aar_stereo::ToStereoGeometry(left_info, right_info);
  } catch (const std::invalid_argument&) {
  }
  if (geometry) {
    FUZZ_CHECK(geometry->width > 0 && geometry->height > 0, "a geometry has a size");
    const cv::Rect roi = aar_stereo::ProjectedRoi(PredictedReceiver(), *geometry, 16);
    FUZZ_CHECK((roi & cv::Rect(0, 0, geometry->width, geometry->height)) == roi,
               "the region of interest lies in the image");
  }

  sensor_msgs::Image left_image, right_image;
  if (!aar_fuzz::NextMessage<sensor_msgs::Image_>(stream, left_image) ||
      !aar_fuzz::NextMessage<sensor_msgs::Image_>(stream, right_image))
    return 0;
  cv::Mat left, right;
  try {
    left = aar_stereo::ToMono8(left_image, "left");
    right = aar_stereo::ToMono8(right_image, "right");
  } catch (const std::invalid_argument&) {
    return 0;
  }
  FUZZ_CHECK(left.rows == static_cast<int>(left_image.height) &&
                 left.cols == static_cast<int>(left_image.width) && left.type() == CV_8UC1,
             "ToMono8 views the whole image");
  if (!geometry) return 0;

  // Block matching with the thesis's settings, semi-global with defaults (as stereo.yaml's two).
  static const aar_stereo::StereoProcessor block_matching{aar_stereo::StereoOptions{}};
  static const aar_stereo::StereoProcessor semi_global = [] {
    aar_stereo::StereoOptions o;
    o.matcher = aar_stereo::Matcher::kSemiGlobal;
    o.block_size = 5;
    o.decimation = aar_stereo::Decimation::kVoxelGrid;
    return aar_stereo::StereoProcessor(o);
  }();
  const aar_stereo::StereoProcessor& processor =
      left_image.header.seq % 2 == 0 ? block_matching : semi_global;
  Match(processor, left, right, *geometry, std::nullopt, left_image.header);
  Match(processor, left, right, *geometry,
        aar_stereo::ProjectedRoi(PredictedReceiver(), *geometry, 16), left_image.header);
  return 0;
}
