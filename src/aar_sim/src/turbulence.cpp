#include "aar_sim/turbulence.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace aar_sim {
namespace {

// MIL-F-8785C figure 7, "high-altitude" turbulence intensity sigma [ft/s] against altitude [ft]
// for the probabilities of exceedance 1e-2 (light), 1e-3 (moderate) and 1e-5 (severe); the same
// table as MathWorks' Dryden block and JSBSim's FGWinds (its POE_Table rows 3, 4 and 6).
constexpr std::array<double, 12> kTableAltitudeFt = {500,   1750,  3750,  7500,  15000, 25000,
                                                     35000, 45000, 55000, 65000, 75000, 80000};
constexpr std::array<double, 12> kSigmaLightFtS = {6.6, 6.9, 7.4, 6.7, 4.6, 2.7,
                                                   0.4, 0.0, 0.0, 0.0, 0.0, 0.0};
constexpr std::array<double, 12> kSigmaModerateFtS = {8.6, 9.6, 10.6, 10.1, 8.0, 6.6,
                                                      5.0, 4.2, 2.7,  0.0,  0.0, 0.0};
constexpr std::array<double, 12> kSigmaSevereFtS = {15.6, 17.6, 23.0, 23.6, 22.1, 20.0,
                                                    16.0, 15.1, 12.1, 7.9,  6.2,  5.1};
constexpr double kMinAltitude = 2000 * kFoot;   // [m] below: the low-altitude model (not here)
constexpr double kMaxAltitude = 80000 * kFoot;  // [m] the table's end

// Standard normal numbers from mt19937_64 by Box-Muller: the same on every standard library
// (std::normal_distribution is implementation-defined).
class Normal {
 public:
  explicit Normal(uint64_t seed) : engine_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = Uniform(), u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }

 private:
  double Uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53; }  // (0,1)
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// A damped second-order low-pass of unit DC gain, x'' = w^2 (in - x) - 2 z w x', stepped by
// semi-implicit Euler (stable and accurate for w * dt << 1: 0.005 here).
struct SecondOrder {
  double x = 0.0, rate = 0.0;
  void Step(double in, double w, double zeta, double dt) {
    rate += dt * (w * w * (in - x) - 2.0 * zeta * w * rate);
    x += dt * rate;
  }
};

void CheckField(bool ok, const std::string& field, const std::string& rule) {
  if (!ok) throw std::invalid_argument("turbulence option " + field + " " + rule);
}

}  // namespace

std::string TurbulenceIntensityName(TurbulenceIntensity intensity) {
  switch (intensity) {
    case TurbulenceIntensity::kNone:
      return "none";
    case TurbulenceIntensity::kLight:
      return "light";
    case TurbulenceIntensity::kModerate:
      return "moderate";
    case TurbulenceIntensity::kSevere:
      return "severe";
  }
  return "none";
}

TurbulenceIntensity ParseTurbulenceIntensity(const std::string& name) {
  for (const TurbulenceIntensity i :
       {TurbulenceIntensity::kNone, TurbulenceIntensity::kLight, TurbulenceIntensity::kModerate,
        TurbulenceIntensity::kSevere}) {
    if (name == TurbulenceIntensityName(i)) return i;
  }
  throw std::invalid_argument(
      "turbulence intensity must be one of none, light, moderate, "
      "severe, not '" +
      name + "'");
}

void CheckTurbulenceOptions(const TurbulenceOptions& o) {
  const auto finite_positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  const auto finite_non_negative = [](double x) { return std::isfinite(x) && x >= 0.0; };
  CheckField(finite_positive(o.airspeed), "airspeed", "must be a finite number > 0 [m/s]");
  CheckField(std::isfinite(o.altitude) && o.altitude >= kMinAltitude && o.altitude <= kMaxAltitude,
             "altitude",
             "must be from 609.6 m to 24384 m (2000 to 80000 ft: the medium/high-altitude model)");
  CheckField(finite_positive(o.wingspan), "wingspan", "must be a finite number > 0 [m]");
  CheckField(finite_positive(o.step) && o.step <= 0.05, "step", "must be in (0, 0.05] s");
  CheckField(finite_positive(o.receiver_frequency) && o.receiver_frequency * o.step < 0.1,
             "receiver_frequency", "must be > 0 and below 0.1 / step [rad/s]");
  CheckField(finite_positive(o.receiver_damping), "receiver_damping", "must be > 0");
  CheckField(o.receiver_position_gain.allFinite() && (o.receiver_position_gain.array() >= 0).all(),
             "receiver_position_gain", "must hold finite numbers >= 0 [s]");
  CheckField(finite_non_negative(o.receiver_pitch_gain), "receiver_pitch_gain",
             "must be a finite number >= 0");
  CheckField(finite_non_negative(o.receiver_yaw_gain), "receiver_yaw_gain",
             "must be a finite number >= 0");
  CheckField(finite_non_negative(o.receiver_roll_gain), "receiver_roll_gain",
             "must be a finite number >= 0 [s]");
  CheckField(finite_positive(o.boom_time_constant) && o.boom_time_constant >= o.step,
             "boom_time_constant", "must be a finite number >= step [s]");
  CheckField(finite_non_negative(o.boom_pitch_gain), "boom_pitch_gain",
             "must be a finite number >= 0");
  CheckField(finite_non_negative(o.boom_roll_gain), "boom_roll_gain",
             "must be a finite number >= 0");
}

double HighAltitudeSigma(TurbulenceIntensity intensity, double altitude) {
  const std::array<double, 12>* table = nullptr;
  switch (intensity) {
    case TurbulenceIntensity::kNone:
      return 0.0;
    case TurbulenceIntensity::kLight:
      table = &kSigmaLightFtS;
      break;
    case TurbulenceIntensity::kModerate:
      table = &kSigmaModerateFtS;
      break;
    case TurbulenceIntensity::kSevere:
      table = &kSigmaSevereFtS;
      break;
  }
  const double h = std::clamp(altitude / kFoot, kTableAltitudeFt.front(), kTableAltitudeFt.back());
  size_t i = 1;
  while (i + 1 < kTableAltitudeFt.size() && kTableAltitudeFt[i] < h) ++i;
  const double f = (h - kTableAltitudeFt[i - 1]) / (kTableAltitudeFt[i] - kTableAltitudeFt[i - 1]);
  return ((1.0 - f) * (*table)[i - 1] + f * (*table)[i]) * kFoot;
}

double DrydenPsdU(double omega, double sigma, double L, double V) {
  const double x = L * omega / V;
  return sigma * sigma * 2.0 * L / (M_PI * V) / (1.0 + x * x);
}

double DrydenPsdVW(double omega, double sigma, double L, double V) {
  const double x = L * omega / V;
  return sigma * sigma * L / (M_PI * V) * (1.0 + 3.0 * x * x) / ((1.0 + x * x) * (1.0 + x * x));
}

std::vector<Gust> DrydenGusts(const TurbulenceOptions& o, size_t n) {
  CheckTurbulenceOptions(o);
  std::vector<Gust> gusts(n);
  const double sigma = HighAltitudeSigma(o.intensity, o.altitude);
  if (sigma == 0.0) return gusts;
  const double V = o.airspeed, L = kDrydenScaleLength, dt = o.step;

  // The Dryden forming filters driven by unit-intensity white noise xi, held over each step
  // (zero-order hold, exact for the linear filters; the hold's sinc^2 is > 0.99 below 5 Hz):
  //   u = sigma sqrt(2 tau) / (1 + tau s) xi,  v, w = sigma sqrt(tau) (1 + sqrt3 tau s) /
  //   (1 + tau s)^2 xi,  p = sqrt(pi C_p) / (1 + tau_p s) xi,  tau = L / V, tau_p = 4 b / (pi V)
  // whose one-sided PSDs |H|^2 / pi are MIL-F-8785C's (DrydenPsdU, DrydenPsdVW, Phi_p).
  // (1 + sqrt3 tau s) / (1 + tau s)^2 = sqrt3 x1 + (1 - sqrt3) x2 with x1 = xi / (1 + tau s),
  // x2 = x1 / (1 + tau s): the cascade's exact discretisation below.
  const double tau = L / V;
  const double a = 1.0 / tau;
  const double e = std::exp(-a * dt);
  const double g1 = 1.0 - e;                   // x1 from the held input
  const double g2 = 1.0 - e * (1.0 + a * dt);  // x2 from the held input
  const double k21 = e * a * dt;               // x2 from x1
  const double b = o.wingspan;
  const double tau_p = 4.0 * b / (M_PI * V);
  const double e_p = std::exp(-dt / tau_p);
  const double c_p = sigma * sigma * 0.8 * std::cbrt(M_PI * L / (4.0 * b)) / (V * L);
  const double gain_u = sigma * std::sqrt(2.0 * tau);
  const double gain_vw = sigma * std::sqrt(tau);
  const double gain_p = std::sqrt(M_PI * c_p);
  const double sqrt3 = std::sqrt(3.0);
  const double input_scale = 1.0 / std::sqrt(dt);  // unit-intensity white noise held for dt

  Normal normal(o.seed);
  double xu = 0.0, xp = 0.0;
  std::array<double, 2> x1{0.0, 0.0}, x2{0.0, 0.0};  // v, w
  for (Gust& g : gusts) {
    g.velocity.x() = gain_u * xu;
    g.velocity.y() = gain_vw * (sqrt3 * x1[0] + (1.0 - sqrt3) * x2[0]);
    g.velocity.z() = gain_vw * (sqrt3 * x1[1] + (1.0 - sqrt3) * x2[1]);
    g.p = gain_p * xp;
    // The next state (noise drawn in a fixed order: u, v, w, p).
    const double nu = normal() * input_scale, nv = normal() * input_scale,
                 nw = normal() * input_scale, np = normal() * input_scale;
    xu = e * xu + g1 * nu;
    const std::array<double, 2> noise{nv, nw};
    for (size_t i = 0; i < 2; ++i) {
      x2[i] = e * x2[i] + k21 * x1[i] + g2 * noise[i];
      x1[i] = e * x1[i] + g1 * noise[i];
    }
    xp = e_p * xp + (1.0 - e_p) * np;
  }
  return gusts;
}

Turbulence::Turbulence(const TurbulenceOptions& options, double end_time)
    : options_(options), end_time_(end_time) {
  CheckTurbulenceOptions(options_);
  if (!enabled()) return;  // the ideal world: no series, any span
  if (!(std::isfinite(end_time) && end_time >= kOrigin && end_time - kOrigin <= kMaxSpan)) {
    throw std::invalid_argument(
        "turbulence: the flight path must end between " + std::to_string(kOrigin) + " and " +
        std::to_string(kOrigin + kMaxSpan) + " s, not at " + std::to_string(end_time) + " s");
  }
  const TurbulenceOptions& o = options_;
  sigma_ = HighAltitudeSigma(o.intensity, o.altitude);
  const double V = o.airspeed, dt = o.step;
  gusts_ = DrydenGusts(o, static_cast<size_t>(std::ceil((end_time - kOrigin) / dt)) + 2);
  perturbations_.resize(gusts_.size());

  std::array<SecondOrder, 6> receiver;  // x, y, z, roll, pitch, yaw
  double boom_pitch = 0.0, boom_roll = 0.0;
  const double e_boom = std::exp(-dt / o.boom_time_constant);
  for (size_t k = 0; k < gusts_.size(); ++k) {
    const Gust& g = gusts_[k];
    TurbulencePerturbation& r = perturbations_[k];
    r.position = Eigen::Vector3d(receiver[0].x, receiver[1].x, receiver[2].x);
    r.rpy = Eigen::Vector3d(receiver[3].x, receiver[4].x, receiver[5].x);
    r.boom_pitch = boom_pitch;
    r.boom_roll = boom_roll;

    // Responses to this step's gust (body x forward, y right, z down; tanker x forward, y left,
    // z up). Downward gust: receiver down, nose down (+pitch about y-left), boom down (+pitch).
    // Gust to the right: receiver right, nose left into it (+yaw). p: roll with it.
    const double alpha_g = g.velocity.z() / V, beta_g = g.velocity.y() / V;  // [rad]
    const std::array<double, 6> in{o.receiver_position_gain.x() * g.velocity.x(),
                                   -o.receiver_position_gain.y() * g.velocity.y(),
                                   -o.receiver_position_gain.z() * g.velocity.z(),
                                   o.receiver_roll_gain * g.p,
                                   o.receiver_pitch_gain * alpha_g,
                                   o.receiver_yaw_gain * beta_g};
    for (size_t i = 0; i < 6; ++i)
      receiver[i].Step(in[i], o.receiver_frequency, o.receiver_damping, dt);
    boom_pitch = e_boom * boom_pitch + (1.0 - e_boom) * o.boom_pitch_gain * alpha_g;
    boom_roll = e_boom * boom_roll + (1.0 - e_boom) * o.boom_roll_gain * beta_g;
  }
}

namespace {

// Index and weight of t on the grid kOrigin + k dt, clamped to [0, n - 1].
std::pair<size_t, double> GridPosition(double t, double origin, double dt, size_t n) {
  const double s = std::clamp((t - origin) / dt, 0.0, static_cast<double>(n - 1));
  const size_t k = std::min(static_cast<size_t>(s), n - 2);
  return {k, s - static_cast<double>(k)};
}

}  // namespace

Gust Turbulence::GustAt(double t) const {
  if (!enabled()) return {};
  const auto [k, f] = GridPosition(std::min(t, end_time_), kOrigin, options_.step, gusts_.size());
  Gust g;
  g.velocity = (1.0 - f) * gusts_[k].velocity + f * gusts_[k + 1].velocity;
  g.p = (1.0 - f) * gusts_[k].p + f * gusts_[k + 1].p;
  return g;
}

TurbulencePerturbation Turbulence::PerturbationAt(double t) const {
  if (!enabled()) return {};
  const auto [k, f] =
      GridPosition(std::min(t, end_time_), kOrigin, options_.step, perturbations_.size());
  const TurbulencePerturbation &a = perturbations_[k], &b = perturbations_[k + 1];
  TurbulencePerturbation r;
  r.position = (1.0 - f) * a.position + f * b.position;
  r.rpy = (1.0 - f) * a.rpy + f * b.rpy;
  r.boom_pitch = (1.0 - f) * a.boom_pitch + f * b.boom_pitch;
  r.boom_roll = (1.0 - f) * a.boom_roll + f * b.boom_roll;
  return r;
}

std::pair<FlightPathRow, BoomPose> Turbulence::Apply(
    double t, FlightPathRow row, BoomPose boom,
    const std::vector<aar_geometry::Joint>& boom_joints) const {
  if (!enabled()) return {std::move(row), boom};
  const TurbulencePerturbation d = PerturbationAt(t);
  row.position_m += d.position;
  row.rpy.roll += d.rpy.x();
  row.rpy.pitch += d.rpy.y();
  row.rpy.yaw += d.rpy.z();
  boom.pitch += d.boom_pitch;
  boom.roll += d.boom_roll;
  // The gusts must not push the boom past its joint limits (the URDF's, as FlightPath checks).
  for (const aar_geometry::Joint& joint : boom_joints) {
    if (!joint.limited()) continue;
    if (joint.name == "boom_pitch") boom.pitch = std::clamp(boom.pitch, joint.lower, joint.upper);
    if (joint.name == "boom_roll") boom.roll = std::clamp(boom.roll, joint.lower, joint.upper);
  }
  if (row.boom) row.boom = boom;
  return {std::move(row), boom};
}

}  // namespace aar_sim
