#include "aar_registration/integrity.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <boost/math/distributions/chi_squared.hpp>

namespace aar_registration {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The largest standard deviation of a 3x3 covariance block (0 for a non-positive one).
double SigmaMax(const Eigen::Matrix3d& block) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (block + block.transpose()),
                                                           Eigen::EigenvaluesOnly);
  const double largest = eig.eigenvalues().maxCoeff();
  return largest > 0.0 ? std::sqrt(largest) : 0.0;
}

// The levels of `covariance` with the factor k = overbound_factor * K(integrity_risk).
ProtectionLevels Levels(const Matrix6d& covariance, double k, const IntegrityOptions& options) {
  ProtectionLevels out;
  out.position_m = k * SigmaMax(covariance.topLeftCorner<3, 3>()) + options.position_bias_m;
  out.attitude_deg =
      k * SigmaMax(covariance.bottomRightCorner<3, 3>()) * kRadToDeg + options.attitude_bias_deg;
  return out;
}

// The overbound factor of `band`'s levels: its own, or the options' when it has none.
double BandFactor(const AlertBand& band, const IntegrityOptions& options) {
  return band.overbound_factor > 0.0 ? band.overbound_factor : options.overbound_factor;
}

}  // namespace

void IntegrityOptions::Validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("integrity: " + what); };
  if (!(integrity_risk > 0.0 && integrity_risk < 1.0)) fail("integrity_risk must lie in (0, 1)");
  if (!(overbound_factor >= 1.0)) fail("overbound_factor must be >= 1");
  if (!(position_bias_m >= 0.0) || !(attitude_bias_deg >= 0.0))
    fail("position_bias and attitude_bias must be >= 0");
  if (bands.empty()) fail("at least one alert band is needed");
  double previous = 0.0;
  for (const AlertBand& b : bands) {
    if (!(b.max_range_m > previous)) fail("alert bands must rise in range");
    if (!(b.position_m > 0.0) || !(b.attitude_deg > 0.0)) fail("alert limits must be > 0");
    if (!(b.overbound_factor == 0.0 || b.overbound_factor >= 1.0))
      fail("a band's overbound_factor must be 0 (the options') or >= 1");
    previous = b.max_range_m;
  }
  if (confirm_frames < 0) fail("confirm_frames must be >= 0");
  if (!(attitude_envelope_deg >= 0.0 && attitude_envelope_deg < 180.0))
    fail("attitude_envelope_deg must lie in [0, 180)");
}

std::string OutsideAttitudeEnvelope(const Eigen::Matrix3d& R, const Eigen::Matrix3d& R_nominal,
                                    double envelope_deg) {
  if (!(envelope_deg > 0.0)) return "";
  const double angle_deg = Eigen::AngleAxisd(R_nominal.transpose() * R).angle() * kRadToDeg;
  if (angle_deg <= envelope_deg) return "";
  std::ostringstream s;
  s << "attitude " << angle_deg << " deg from the formation's nominal > envelope " << envelope_deg
    << " deg";
  return s.str();
}

double ProtectionFactor(double risk, int dof) {
  const boost::math::chi_squared chi2(dof);
  return std::sqrt(boost::math::quantile(boost::math::complement(chi2, risk)));
}

ProtectionLevels ComputeProtectionLevels(const Matrix6d& covariance,
                                         const IntegrityOptions& options, const AlertBand& band) {
  return Levels(covariance, BandFactor(band, options) * ProtectionFactor(options.integrity_risk),
                options);
}

const AlertBand& BandOfRange(const std::vector<AlertBand>& bands, double range_m) {
  for (const AlertBand& b : bands)
    if (range_m <= b.max_range_m) return b;
  return bands.back();
}

IntegrityMonitor::IntegrityMonitor(const IntegrityOptions& options) : options_(options) {
  options_.Validate();
  k_ = ProtectionFactor(options_.integrity_risk);
}

std::string IntegrityMonitor::Confirm(const IntegrityInput& in) {
  const int needed = options_.confirm_frames;
  if (!in.tracking) return "";  // no track: nothing to confirm
  if (in.outcome == TrackOutcome::kStarted)
    confirmed_ = 0;
  else if (in.agreeing)
    confirmed_ = std::min(confirmed_ + 1, needed);
  else if (confirmed_ < needed)
    confirmed_ = 0;  // the agreement must be unbroken
  if (confirmed_ >= needed) return "";
  std::ostringstream s;
  s << "unconfirmed track: " << confirmed_ << " of " << needed
    << " frames in a row with every measurement accepted";
  return s.str();
}

IntegrityResult IntegrityMonitor::Assess(const IntegrityInput& in) {
  IntegrityResult out;
  if (!in.valid) {
    if (in.tracking) confirmed_ = 0;
    out.reason = "no pose";
    return out;
  }
  const std::string unconfirmed = Confirm(in);
  out.confirmed = confirmed_;
  out.covariance = in.covariance;
  if (!unconfirmed.empty()) out.covariance += in.acquisition_covariance;
  out.limits = BandOfRange(options_.bands, in.T_tanker_receiver.translation().norm());
  out.levels = Levels(out.covariance, BandFactor(out.limits, options_) * k_, options_);
  out.risk = options_.integrity_risk;
  std::ostringstream s;
  if (!std::isfinite(out.levels.position_m) || !std::isfinite(out.levels.attitude_deg))
    s << "protection level not finite; ";
  if (out.levels.position_m > out.limits.position_m)
    s << "position protection level " << out.levels.position_m << " m > alert limit "
      << out.limits.position_m << " m; ";
  if (out.levels.attitude_deg > out.limits.attitude_deg)
    s << "attitude protection level " << out.levels.attitude_deg << " deg > alert limit "
      << out.limits.attitude_deg << " deg; ";
  const std::string envelope = OutsideAttitudeEnvelope(
      in.T_tanker_receiver.linear(), in.R_tanker_receiver_nominal, options_.attitude_envelope_deg);
  if (!envelope.empty()) s << envelope << "; ";
  if (!unconfirmed.empty()) s << unconfirmed << "; ";
  out.reason = s.str();
  if (!out.reason.empty()) out.reason.resize(out.reason.size() - 2);
  out.alert = !out.reason.empty();
  return out;
}

}  // namespace aar_registration
