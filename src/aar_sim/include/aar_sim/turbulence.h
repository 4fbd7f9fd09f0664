#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <aar_geometry/robot_model.h>

#include "aar_sim/flight_path.h"

namespace aar_sim {

// Atmospheric turbulence (docs/realism/turbulence.md): Dryden gusts of MIL-F-8785C, section
// 3.7.2 (the forms and the medium/high-altitude parameters as MathWorks' Aerospace Blockset
// documents them, "Dryden Wind Turbulence Model (Continuous)"), and a simple response of a
// station-keeping receiver and of the boom to them.

// MIL-F-8785C's intensities by the probability of exceeding the high-altitude intensity:
// light 1e-2, moderate 1e-3, severe 1e-5. None: the ideal world (no perturbation).
enum class TurbulenceIntensity { kNone, kLight, kModerate, kSevere };

// "none", "light", "moderate", "severe": the name of an intensity and back (an unknown name
// throws std::invalid_argument listing the choices).
std::string TurbulenceIntensityName(TurbulenceIntensity intensity);
TurbulenceIntensity ParseTurbulenceIntensity(const std::string& name);

struct TurbulenceOptions {
  TurbulenceIntensity intensity = TurbulenceIntensity::kNone;
  uint64_t seed = 1;         // the gusts are a function of (seed, t) only
  double airspeed = 130.0;   // [m/s] true airspeed V (~250 KTAS, a boom-refuelling speed)
  double altitude = 6000.0;  // [m] (~20000 ft); medium/high altitude: 609.6 m (2000 ft) to 24384 m
  double wingspan = 16.6;    // [m] the receiver's (C-12: 54.5 ft), for the roll gust p
  double step = 0.01;        // [s] internal step of the filters (100 Hz)

  // The receiver's response: a station-keeping loop (pilot or autopilot), per axis a damped
  // second-order low-pass of unit DC gain, times a gain.
  double receiver_frequency = 0.5;  // [rad/s] natural frequency of the position/attitude loop
  double receiver_damping = 0.7;
  // [s] displacement per gust speed [m/s], tanker x (from u), y (from v), z (from w)
  Eigen::Vector3d receiver_position_gain = Eigen::Vector3d(0.1, 0.2, 0.25);
  double receiver_pitch_gain = 0.5;  // [-] pitch per gust angle of attack w/V
  double receiver_yaw_gain = 0.5;    // [-] yaw per gust sideslip v/V
  double receiver_roll_gain = 1.0;   // [s] roll per roll gust p [rad/s]

  // The boom: first-order lag of its aerodynamic response; extension untouched.
  double boom_time_constant = 0.5;  // [s]
  double boom_pitch_gain = 0.5;     // [-] boom pitch per gust angle of attack w/V
  double boom_roll_gain = 0.5;      // [-] boom roll (lateral swing) per gust sideslip v/V
};

// Throws std::invalid_argument naming the field for a value out of range (a non-positive or
// non-finite airspeed, step or gain time constant, an altitude outside 609.6 to 24384 m, ...).
void CheckTurbulenceOptions(const TurbulenceOptions& options);

constexpr double kFoot = 0.3048;                     // [m]
constexpr double kDrydenScaleLength = 1750 * kFoot;  // [m] L_u = L_v = L_w above 2000 ft

// [m/s] sigma_u = sigma_v = sigma_w at `altitude` [m] (MIL-F-8785C figure 7, interpolated
// linearly in altitude); 0 for kNone.
double HighAltitudeSigma(TurbulenceIntensity intensity, double altitude);

// The Dryden power spectral densities [(m/s)^2 / (rad/s)], one-sided in omega [rad/s] (their
// integral over 0..inf is sigma^2), for sigma [m/s], scale length L [m], airspeed V [m/s].
double DrydenPsdU(double omega, double sigma, double L, double V);
double DrydenPsdVW(double omega, double sigma, double L, double V);  // v and w: same form

// Gust state at one time: body axes (x forward, y right, z down, as MIL-F-8785C).
struct Gust {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // [m/s] u, v, w
  double p = 0.0;                                      // [rad/s] roll gust
};

// What the gusts do to the receiver and the boom at one time, relative to the flight path.
struct TurbulencePerturbation {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // [m] receiver, tanker frame
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();       // [rad] receiver roll, pitch, yaw
  double boom_pitch = 0.0;                             // [rad]
  double boom_roll = 0.0;                              // [rad]
};

// n steps of the Dryden gusts from filters at rest (options.step apart; seeded by options.seed).
// Throws std::invalid_argument for bad options.
std::vector<Gust> DrydenGusts(const TurbulenceOptions& options, size_t n);

// Seeded Dryden gusts over a time span and their effect. The filters start at rest at
// kOrigin and run at `step`, so the state at time t depends only on (options, t):
// two spans that overlap agree there, whatever the frame rate that samples them.
class Turbulence {
 public:
  static constexpr double kOrigin = -120.0;    // [s] where the series starts (30 L/V of warm-up)
  static constexpr double kMaxSpan = 20000.0;  // [s] longest series (~100 bytes per 0.01 s)

  // Precomputes the series over [kOrigin, end_time] (intensity none: nothing). Throws
  // std::invalid_argument for bad options (CheckTurbulenceOptions) or, when enabled, an end_time
  // that is not finite, before kOrigin or more than kMaxSpan after it. Times before kOrigin get
  // the state at kOrigin (at rest).
  Turbulence(const TurbulenceOptions& options, double end_time);

  bool enabled() const { return options_.intensity != TurbulenceIntensity::kNone; }
  const TurbulenceOptions& options() const { return options_; }
  double sigma() const { return sigma_; }  // [m/s]

  // Interpolated linearly between steps; t clamped to [kOrigin, end_time]. Zero when disabled.
  Gust GustAt(double t) const;
  TurbulencePerturbation PerturbationAt(double t) const;

  // The path's row and boom pose at t with the perturbation at t added (the boom's pitch and
  // roll clamped to the limits of `boom_joints`' boom_pitch and boom_roll, when given). Disabled:
  // row and boom unchanged, bit for bit.
  std::pair<FlightPathRow, BoomPose> Apply(
      double t, FlightPathRow row, BoomPose boom,
      const std::vector<aar_geometry::Joint>& boom_joints = {}) const;

  // The gust series on the step grid from kOrigin (for the spectra test and the figure).
  const std::vector<Gust>& gusts() const { return gusts_; }

 private:
  TurbulenceOptions options_;
  double sigma_ = 0.0;
  double end_time_ = 0.0;
  std::vector<Gust> gusts_;
  std::vector<TurbulencePerturbation> perturbations_;
};

}  // namespace aar_sim
