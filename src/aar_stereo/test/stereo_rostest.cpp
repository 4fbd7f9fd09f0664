#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <mutex>

#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <stereo_msgs/DisparityImage.h>

namespace {

template <typename Msg>
struct Collector {
  std::mutex mutex;
  std::map<ros::Time, boost::shared_ptr<const Msg>> by_stamp;
  ros::Subscriber sub;
  Collector(ros::NodeHandle& nh, const std::string& topic) {
    sub = nh.subscribe<Msg>(topic, 10, [this](const boost::shared_ptr<const Msg>& m) {
      std::lock_guard<std::mutex> lock(mutex);
      by_stamp[m->header.stamp] = m;
    });
  }
  size_t size() {
    std::lock_guard<std::mutex> lock(mutex);
    return by_stamp.size();
  }
};

const float* Floats(const sensor_msgs::Image& image, int v) {
  return reinterpret_cast<const float*>(&image.data[static_cast<size_t>(v) * image.step]);
}

TEST(Compare, DisparityAndCloudMatchStereoImageProc) {
  ros::NodeHandle nh;
  Collector<stereo_msgs::DisparityImage> ours(nh, "/stereo/disparity"),
      theirs(nh, "/sip/disparity");
  Collector<sensor_msgs::PointCloud2> our_points(nh, "/stereo/points2"),
      their_points(nh, "/sip/points2");
  // Common stamps of all four outputs; 3 frames.
  std::vector<ros::Time> common;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(150.0);
  while (ros::WallTime::now() < deadline && common.size() < 3) {
    ros::WallDuration(0.2).sleep();
    std::lock_guard<std::mutex> a(ours.mutex), b(theirs.mutex), c(our_points.mutex),
        d(their_points.mutex);
    common.clear();
    for (const auto& [stamp, msg] : ours.by_stamp) {
      if (theirs.by_stamp.count(stamp) && our_points.by_stamp.count(stamp) &&
          their_points.by_stamp.count(stamp)) {
        common.push_back(stamp);
      }
    }
  }
  ASSERT_GE(common.size(), 3u) << "fewer than 3 frames processed by both within 150 s";

  for (const ros::Time& stamp : common) {
    const auto& a = ours.by_stamp.at(stamp)->image;
    const auto& b = theirs.by_stamp.at(stamp)->image;
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    long valid = 0, agree = 0;
    for (uint32_t v = 0; v < a.height; ++v) {
      const float *ra = Floats(a, v), *rb = Floats(b, v);
      for (uint32_t u = 0; u < a.width; ++u) {
        const bool va = ra[u] >= 0.0f,
                   vb = rb[u] >= 0.0f;  // both mark invalid as min_disparity - 1 = -1
        if (!va && !vb) continue;
        ++valid;
        agree += va && vb && std::abs(ra[u] - rb[u]) < 1e-4f;
      }
    }
    const double agreement = static_cast<double>(agree) / valid;
    std::printf("[ compare ] frame %.1f: %ld valid disparity pixels, %.4f%% identical\n",
                stamp.toSec(), valid, 100.0 * agreement);
    EXPECT_GT(valid, 10000);
    EXPECT_GE(agreement, 0.999);

    // Organized clouds, pixel for pixel: where both have a point, within 1 mm.
    const auto& pa = *our_points.by_stamp.at(stamp);
    const auto& pb = *their_points.by_stamp.at(stamp);
    ASSERT_EQ(pa.width * pa.height, pb.width * pb.height);
    sensor_msgs::PointCloud2ConstIterator<float> xa(pa, "x"), xb(pb, "x");
    long both = 0, within = 0, only_one = 0;
    double worst = 0.0;
    for (size_t i = 0; i < static_cast<size_t>(pa.width) * pa.height; ++i, ++xa, ++xb) {
      const bool fa = std::isfinite(xa[2]), fb = std::isfinite(xb[2]);
      if (fa != fb) ++only_one;
      if (!fa || !fb) continue;
      ++both;
      const double d =
          std::sqrt((xa[0] - xb[0]) * (xa[0] - xb[0]) + (xa[1] - xb[1]) * (xa[1] - xb[1]) +
                    (xa[2] - xb[2]) * (xa[2] - xb[2]));
      worst = std::max(worst, d);
      within += d < 1e-3;
    }
    std::printf(
        "[ compare ] frame %.1f: %ld points in both clouds, largest difference %.3g m, %ld in one "
        "only\n",
        stamp.toSec(), both, worst, only_one);
    EXPECT_EQ(within, both);
    EXPECT_LE(only_one, valid / 1000);
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "aar_stereo_rostest");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
