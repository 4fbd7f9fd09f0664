#include "aar_sim/ros/conversions.h"

#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <boost/make_shared.hpp>

namespace aar_sim {

sensor_msgs::ImagePtr ToImageMsg(const Image<uint8_t>& image, const std_msgs::Header& header) {
  auto msg = boost::make_shared<sensor_msgs::Image>();
  msg->header = header;
  msg->height = image.height;
  msg->width = image.width;
  msg->encoding = sensor_msgs::image_encodings::MONO8;
  msg->is_bigendian = false;
  msg->step = image.width;
  msg->data = image.data;
  return msg;
}

sensor_msgs::CameraInfoPtr ToCameraInfoMsg(const CameraIntrinsics& k, double Tx,
                                           const std_msgs::Header& header) {
  auto msg = boost::make_shared<sensor_msgs::CameraInfo>();
  msg->header = header;
  msg->height = k.height;
  msg->width = k.width;
  msg->distortion_model = "plumb_bob";
  msg->D.assign(5, 0.0);
  msg->K = {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0};
  msg->R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  msg->P = {k.fx, 0.0, k.cx, Tx, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return msg;
}

sensor_msgs::CameraInfoPtr ToRawCameraInfoMsg(const RawCamera& camera,
                                              const CameraIntrinsics& rectified, double Tx,
                                              const std_msgs::Header& header) {
  auto msg = ToCameraInfoMsg(rectified, Tx, header);
  const CameraIntrinsics& k = camera.K();
  msg->D.assign(camera.D().begin(), camera.D().end());
  msg->K = {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) msg->R[size_t(3 * i + j)] = camera.R_rect_raw()(i, j);
  return msg;
}

geometry_msgs::TransformStamped ToTransformMsg(const Eigen::Isometry3d& T, const ros::Time& stamp,
                                               const std::string& parent,
                                               const std::string& child) {
  geometry_msgs::TransformStamped msg = tf2::eigenToTransform(T);
  msg.header.stamp = stamp;
  msg.header.frame_id = parent;
  msg.child_frame_id = child;
  return msg;
}

}  // namespace aar_sim
