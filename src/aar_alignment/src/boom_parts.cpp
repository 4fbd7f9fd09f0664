#include "aar_alignment/boom_parts.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace aar_alignment {

std::vector<std::vector<Eigen::Vector3d>> BoomPartsInTanker(
    const std::vector<aar_description::BoomCollisionPart>& parts,
    const std::map<std::string, Eigen::Isometry3d>& T_tanker_links) {
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (const aar_description::BoomCollisionPart& part : parts) {
    const auto link = T_tanker_links.find(part.link);
    if (link == T_tanker_links.end()) continue;
    const Eigen::Isometry3d T = link->second * part.T_link_part;
    std::vector<Eigen::Vector3d> vertices;
    vertices.reserve(part.mesh.vertices.size());
    for (const auto& v : part.mesh.vertices) vertices.push_back(T * v);
    out.push_back(std::move(vertices));
  }
  return out;
}

cv::Mat BoomMask(const PinholeCamera& c, const std::vector<std::vector<Eigen::Vector3d>>& parts,
                 double margin) {
  if (parts.empty()) return {};
  const Eigen::Isometry3d T_optical_tanker = c.T_tanker_optical.inverse();
  constexpr double kNear = 0.05;  // [m]
  cv::Mat mask = cv::Mat::zeros(c.height, c.width, CV_8U);
  for (const auto& part : parts) {
    std::vector<Eigen::Vector3d> front, back;
    for (const auto& p : part)
      (T_optical_tanker * p).z() > kNear ? front.push_back(T_optical_tanker * p)
                                         : back.push_back(T_optical_tanker * p);
    std::vector<Eigen::Vector3d> kept = front;
    for (const auto& a : front)
      for (const auto& b : back) kept.push_back(b + (a - b) * (kNear - b.z()) / (a.z() - b.z()));
    if (front.empty()) continue;
    std::vector<cv::Point2f> pixels;
    for (const auto& y : kept)
      pixels.emplace_back(c.fx * y.x() / y.z() + c.cx, c.fy * y.y() / y.z() + c.cy);
    std::vector<cv::Point2f> hull;
    cv::convexHull(pixels, hull);
    cv::Point2f centre(0.f, 0.f);
    for (const auto& h : hull) centre += h / static_cast<float>(hull.size());
    std::vector<cv::Point> grown;
    for (const auto& h : hull) {
      const cv::Point2f d = h - centre;
      const float len = std::max(1e-3f, std::hypot(d.x, d.y));
      const cv::Point2f g = h + d * static_cast<float>(margin / len);
      grown.emplace_back(static_cast<int>(std::lround(std::clamp(g.x, -1e6f, 1e6f))),
                         static_cast<int>(std::lround(std::clamp(g.y, -1e6f, 1e6f))));
    }
    cv::fillConvexPoly(mask, grown, cv::Scalar(1));
  }
  return mask;
}

}  // namespace aar_alignment
