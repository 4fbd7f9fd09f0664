#include "aar_geometry/receiver_reference.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <embree3/rtcore.h>

#include "aar_geometry/surface_sampling.h"

namespace aar_geometry {

ReferenceCloud ReferenceCloud::Subset(const std::vector<bool>& keep) const {
  if (keep.size() != points.size())
    throw std::invalid_argument("Subset: one flag per point needed");
  ReferenceCloud out;
  out.part_names = part_names;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!keep[i]) continue;
    out.points.push_back(points[i]);
    out.normals.push_back(normals[i]);
    out.parts.push_back(parts[i]);
  }
  return out;
}

ReferenceCloud ReferenceCloud::Select(const std::vector<std::string>& wanted) const {
  std::vector<bool> part_kept(part_names.size(), false);
  for (const auto& name : wanted) {
    const auto it = std::find(part_names.begin(), part_names.end(), name);
    if (it == part_names.end())
      throw std::invalid_argument("reference model has no part '" + name + "'");
    part_kept[it - part_names.begin()] = true;
  }
  std::vector<bool> keep(points.size());
  for (size_t i = 0; i < points.size(); ++i) keep[i] = part_kept[parts[i]];
  return Subset(keep);
}

ReferenceCloud SampleReceiver(const TriangleMesh& receiver, const ReferenceModelOptions& options) {
  SurfaceSamplingOptions sampling;
  sampling.points_per_m2 = options.points_per_m2;
  sampling.seed = options.seed;
  const SurfaceSamples samples = SampleSurface(receiver, sampling);
  ReferenceCloud cloud;
  cloud.points = samples.points;
  cloud.normals = samples.normals;
  cloud.parts = samples.parts;
  cloud.part_names = receiver.part_names;
  return cloud;
}

struct VisibilityTester::Bvh {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

namespace {

// True when the ray from `origin` along unit `d` hits the scene before `tfar` [m].
bool Occluded(RTCScene scene, RTCIntersectContext* context, const Eigen::Vector3d& origin,
              const Eigen::Vector3d& d, float tfar) {
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x());
  ray.org_y = static_cast<float>(origin.y());
  ray.org_z = static_cast<float>(origin.z());
  ray.dir_x = static_cast<float>(d.x());
  ray.dir_y = static_cast<float>(d.y());
  ray.dir_z = static_cast<float>(d.z());
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = 0xffffffff;
  rtcOccluded1(scene, context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to -inf when something is hit
}

// Embree (Debian builds it with assertions) aborts the process on a ray whose origin or
// direction is beyond about 1.8e18 or whose tfar is not a number; a cloud can carry finite
// coordinates of 1e20. Such a ray is not cast.
bool EmbreeCanCast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, float tfar) {
  constexpr double kLargest = 1e18;  // Embree's FLT_LARGE is 1.844e18
  return origin.allFinite() && d.allFinite() && origin.cwiseAbs().maxCoeff() < kLargest &&
         d.cwiseAbs().maxCoeff() < kLargest && tfar >= 0.0f;  // false for NaN too
}

// One occlusion ray per index through one intersect context: `make_ray(i, origin, direction,
// tfar)` sets ray i and returns false to skip it. Entry i is `hit == when_hit` for a ray cast,
// false for one skipped (by make_ray or as one Embree cannot cast).
template <typename MakeRay>
std::vector<bool> CastEach(RTCScene scene, size_t n, bool when_hit, MakeRay make_ray) {
  std::vector<bool> out(n, false);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  Eigen::Vector3d origin, direction;
  float tfar = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    if (make_ray(i, origin, direction, tfar) && EmbreeCanCast(origin, direction, tfar))
      out[i] = Occluded(scene, &context, origin, direction, tfar) == when_hit;
  }
  return out;
}

}  // namespace

VisibilityTester::VisibilityTester(const TriangleMesh& mesh) : bvh_(std::make_unique<Bvh>()) {
  mesh.Validate();
  bvh_->device = rtcNewDevice("threads=1");  // deterministic, and the caller owns the cores
  if (!bvh_->device) throw std::runtime_error("Embree device could not be created");
  bvh_->scene = rtcNewScene(bvh_->device);
  RTCGeometry geometry = rtcNewGeometry(bvh_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(bvh_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(bvh_->scene);
}

VisibilityTester::~VisibilityTester() {
  if (bvh_->scene) rtcReleaseScene(bvh_->scene);
  if (bvh_->device) rtcReleaseDevice(bvh_->device);
}

std::vector<bool> VisibilityTester::Visible(const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<Eigen::Vector3d>& normals,
                                            const Eigen::Vector3d& eye, double tolerance) const {
  if (normals.size() != points.size())
    throw std::invalid_argument("Visible: one normal per point needed");
  return CastEach(bvh_->scene, points.size(), false,
                  [&](size_t i, Eigen::Vector3d& origin, Eigen::Vector3d& d, float& tfar) {
                    const Eigen::Vector3d to_point = points[i] - eye;
                    const double distance = to_point.norm();
                    if (!(distance > tolerance) || normals[i].dot(to_point) >= 0.0)
                      return false;  // too close, or faces away: not visible
                    origin = eye;
                    d = to_point / distance;
                    tfar = static_cast<float>(distance - tolerance);
                    return true;
                  });
}

std::vector<bool> VisibilityTester::RaysHit(const std::vector<Eigen::Vector3d>& origins,
                                            const std::vector<Eigen::Vector3d>& directions) const {
  if (origins.size() != directions.size())
    throw std::invalid_argument("RaysHit: one direction per origin needed");
  return CastEach(bvh_->scene, origins.size(), true,
                  [&](size_t i, Eigen::Vector3d& origin, Eigen::Vector3d& d, float& tfar) {
                    if (!origins[i].allFinite() || !directions[i].allFinite()) return false;
                    origin = origins[i];
                    d = directions[i];
                    tfar = std::numeric_limits<float>::infinity();
                    return true;
                  });
}

ReferenceCloud Shell(const ReferenceCloud& dense, const VisibilityTester& receiver,
                     const std::vector<Eigen::Vector3d>& eyes, double tolerance) {
  std::vector<bool> keep(dense.size(), true);
  for (const auto& eye : eyes) {
    const std::vector<bool> seen = receiver.Visible(dense.points, dense.normals, eye, tolerance);
    for (size_t i = 0; i < keep.size(); ++i) keep[i] = keep[i] && seen[i];
  }
  return dense.Subset(keep);
}

namespace {

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw std::invalid_argument("centroid of an empty cloud");
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p;
  return c / static_cast<double>(points.size());
}

}  // namespace

Eigen::Isometry3d CentroidSeed(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                               const std::vector<Eigen::Vector3d>& reference_in_receiver) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();  // the tanker's orientation
  T.translation() = Centroid(sensed_in_tanker) - Centroid(reference_in_receiver);
  return T;
}

std::vector<Eigen::Vector3d> DensestBall(const std::vector<Eigen::Vector3d>& points, double radius,
                                         int candidates) {
  if (points.empty()) throw std::invalid_argument("densest ball of an empty cloud");
  if (!(radius > 0.0)) throw std::invalid_argument("densest ball: radius must be positive");
  if (candidates < 1) throw std::invalid_argument("densest ball: candidates must be >= 1");
  const double r2 = radius * radius;
  auto count = [&](const Eigen::Vector3d& c) {
    size_t n = 0;
    for (const auto& p : points) n += (p - c).squaredNorm() <= r2;
    return n;
  };
  // Brute force: 256 candidates x 15,000 points is a few milliseconds, once per acquisition.
  const size_t step = std::max<size_t>(1, points.size() / static_cast<size_t>(candidates));
  Eigen::Vector3d centre = points.front();
  size_t best = 0;
  for (size_t i = 0; i < points.size(); i += step) {
    const size_t n = count(points[i]);
    if (n > best) best = n, centre = points[i];
  }
  std::vector<Eigen::Vector3d> inside;
  for (int iteration = 0; iteration < 5; ++iteration) {
    inside.clear();
    for (const auto& p : points)
      if ((p - centre).squaredNorm() <= r2) inside.push_back(p);
    const Eigen::Vector3d moved = Centroid(inside);
    if ((moved - centre).norm() < 1e-3 * radius) break;
    centre = moved;
  }
  inside.clear();
  for (const auto& p : points)
    if ((p - centre).squaredNorm() <= r2) inside.push_back(p);
  return inside.empty() ? std::vector<Eigen::Vector3d>{centre} : inside;
}

double HalfDiagonal(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return 0.0;
  Eigen::AlignedBox3d box;
  for (const auto& p : points) box.extend(p);
  return 0.5 * box.diagonal().norm();
}

}  // namespace aar_geometry
