#include "aar_sim/approach.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <aar_geometry/pose.h>

namespace aar_sim {

namespace {

using aar_geometry::DegToRad;

double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Smooth seeded wander: a sum of three sines of random phase and period 8 to 30 s, in [-1, 1].
struct Wander {
  double amplitude[3], period[3], phase[3];
  explicit Wander(std::mt19937_64& rng) {
    for (int i = 0; i < 3; ++i) {
      amplitude[i] = 0.2 + 0.8 * Uniform01(rng);
      period[i] = 8.0 + 22.0 * Uniform01(rng);
      phase[i] = 2.0 * M_PI * Uniform01(rng);
    }
  }
  double operator()(double t) const {
    double v = 0.0, norm = 0.0;
    for (int i = 0; i < 3; ++i) {
      v += amplitude[i] * std::sin(2.0 * M_PI * t / period[i] + phase[i]);
      norm += amplitude[i];
    }
    return v / norm;
  }
};

}  // namespace

std::vector<FlightPathRow> GenerateApproach(const ApproachOptions& o,
                                            const Eigen::Vector3d& contact_receptacle) {
  if (!(o.rate > 0.0) || !(o.far_speed > 0.0) || !(o.mid_speed > 0.0) || !(o.near_speed > 0.0)) {
    throw std::invalid_argument("approach rates and speeds must be positive");
  }
  if (!(std::abs(o.azimuth) < 45.0) || !(o.elevation > -45.0 && o.elevation < 45.0))
    throw std::invalid_argument("approach azimuth and elevation must be within +/-45 deg");
  if (!(o.boom_swing >= 0.0 && o.boom_swing <= 1.0))
    throw std::invalid_argument("boom_swing must be in [0, 1]");
  const aar_geometry::RollPitchYaw trim{0.0, -DegToRad(o.pitch), 0.0};  // REP-103: nose up < 0
  const Eigen::Matrix3d R_trim = aar_geometry::RotationFromRollPitchYaw(trim);
  const Eigen::Vector3d contact = contact_receptacle - R_trim * o.receptacle;
  const double contact_range = contact.norm();
  if (o.start_range <= contact_range)
    throw std::invalid_argument("start range inside contact range");

  // Straight line from the start point (behind and below contact) to contact; find the distance
  // along it that puts the start at start_range from the tanker origin.
  const double el = DegToRad(o.elevation);
  const double az = DegToRad(o.azimuth);
  const Eigen::Vector3d back(-std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                             -std::sin(el));  // from contact towards start
  const double b = contact.dot(back);
  const double along =
      -b + std::sqrt(b * b - contact.squaredNorm() + o.start_range * o.start_range);

  std::mt19937_64 rng(o.seed);
  Wander wx(rng), wy(rng), wz(rng), wroll(rng), wpitch(rng), wyaw(rng);
  Wander wboom_pitch(rng), wboom_roll(rng), wboom_extension(rng);  // after: the default is kept
  const BoomPose rest = aar_description::DefaultBoomPose();
  std::vector<FlightPathRow> rows;
  double s = along;  // distance still to fly [m]
  const double dt = 1.0 / o.rate;
  double t = 0.0, hold_left = o.hold;
  while (true) {
    const Eigen::Vector3d nominal = contact + s * back;
    const double range = nominal.norm();
    const double fade = std::min(1.0, s / 40.0);  // wander dies out over the last 40 m
    FlightPathRow row;
    row.t = t;
    row.position_m =
        nominal + fade * o.position_wander * Eigen::Vector3d(wx(t), wy(t), 0.5 * wz(t));
    row.rpy = {fade * DegToRad(o.attitude_wander) * wroll(t),
               trim.pitch + fade * DegToRad(o.attitude_wander) * 0.5 * wpitch(t),
               fade * DegToRad(o.attitude_wander) * wyaw(t)};
    if (o.boom_swing > 0.0) {
      const double swing = o.boom_swing * std::clamp((range - 45.0) / 15.0, 0.0, 1.0);
      row.boom = BoomPose{rest.pitch + swing * DegToRad(5.0) * wboom_pitch(t),
                          rest.roll + swing * DegToRad(8.0) * wboom_roll(t),
                          rest.extension + swing * 0.5 * (1.0 + wboom_extension(t))};
    }
    rows.push_back(row);
    if (s <= 0.0) {
      if (hold_left <= 0.0) break;
      hold_left -= dt;
    }
    const double speed = range > 70.0 ? o.far_speed : range > 50.0 ? o.mid_speed : o.near_speed;
    s = std::max(0.0, s - speed * dt);
    t = std::round((t + dt) * 1e6) / 1e6;
  }
  return rows;
}

ApproachOptions VariedApproach(uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x5eed5eedULL);
  auto between = [&](double a, double b) { return a + (b - a) * Uniform01(rng); };
  ApproachOptions o;
  o.elevation = between(8.0, 18.0);
  o.azimuth = between(-10.0, 10.0);
  o.far_speed = between(4.0, 8.0);
  o.mid_speed = between(1.5, 3.5);
  o.near_speed = between(0.4, 0.9);
  o.position_wander = between(0.2, 1.0);
  o.attitude_wander = between(0.5, 2.5);
  o.boom_swing = between(0.0, 1.0);
  o.seed = seed;
  return o;
}

}  // namespace aar_sim
