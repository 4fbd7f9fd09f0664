#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "aar_registration/tracker.h"
#include "aar_registration/types.h"

namespace aar_registration {

// The alert limits of one phase of the approach: estimates whose range from the tanker's origin
// is at most max_range_m (and beyond the previous band's). docs/INTEGRITY.md gives the rationale.
struct AlertBand {
  double max_range_m = std::numeric_limits<double>::infinity();  // [m]
  double position_m = 0.0;                                       // [m] 3D position error
  double attitude_deg = 0.0;                                     // [deg] rotation angle
  // The overbound factor of the levels in this phase (IntegrityOptions::overbound_factor's
  // meaning); 0: that one. Far out the errors are the alignment's biases more than its noise.
  double overbound_factor = 0.0;
};

// Integrity monitoring (not in the thesis): each pose's protection levels, bounds on its error
// that fail with probability integrity_risk per frame, and an alert when they exceed the phase's
// alert limits or the track is not yet confirmed (docs/INTEGRITY.md).
struct IntegrityOptions {
  // Per frame: the probability that the error exceeds its protection level without an alert.
  double integrity_risk = 1e-5;
  // The levels overbound the error distribution (GNSS's way: an inflated Gaussian and a bias):
  // level = overbound_factor * K(integrity_risk) * sigma_max + bias, where sigma_max is the
  // covariance's largest standard deviation of the 3 positions (or rotations) and K the
  // chi-square bound of a 3D error at the risk. Calibrated on seeds the reports do not use: the
  // largest error in sigma_max of any frame not in alert, over suite seed 7's 8 flights of the
  // C-12 (both worlds), was 7.61 (docs/INTEGRITY.md), 1.50 K(1e-5). A band may carry its own
  // (AlertBand::overbound_factor), as flight's do.
  double overbound_factor = 1.5;
  double position_bias_m = 0.0;    // [m]
  double attitude_bias_deg = 0.0;  // [deg]
  // By range, nearest first (region C, B, A by default); the last one reaches any range.
  std::vector<AlertBand> bands = {{38.0, 0.5, 2.0},  // C: contact, the boom's nozzle in reach
                                  {70.0, 2.0, 5.0},  // B: pre-contact, station keeping
                                  {std::numeric_limits<double>::infinity(), 10.0, 10.0}};  // A
  // A new track is in alert until this many consecutive frames had their registration and
  // (with the outline) their outline both accepted by the filter: a start can be wrong. 0: a
  // start is trusted at once (only to show what the confirmation buys).
  int confirm_frames = 5;
  // The formation's attitude envelope (not in the thesis) [deg]: a receiver in the refuelling
  // envelope flies within a few degrees of the tanker's attitude (every approach of the suites
  // within 3.0 deg of the nominal, docs/INTEGRITY.md), so a pose turned further than this from
  // the nominal attitude (RegistrarOptions::T_tanker_receiver_nominal) is a wrong one: an alert,
  // and with tracking a start refused and a track dropped. 0: off.
  double attitude_envelope_deg = 0.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct ProtectionLevels {
  double position_m = 0.0;    // [m] bound on |t_estimate - t_true|
  double attitude_deg = 0.0;  // [deg] bound on the angle of R_true^T R_estimate
};

// sqrt of the chi-square quantile with `dof` degrees of freedom at 1 - risk: a zero-mean
// Gaussian error's norm exceeds K * sigma_max with probability at most `risk`.
double ProtectionFactor(double risk, int dof = 3);

// The levels of a covariance ([m^2, rad^2]: position, then rotation) under `options`, with the
// overbound factor of `band` (its own, or the options' when it has none).
ProtectionLevels ComputeProtectionLevels(const Matrix6d& covariance,
                                         const IntegrityOptions& options,
                                         const AlertBand& band = {});

// The band whose range holds `range_m` (the last one beyond every other).
const AlertBand& BandOfRange(const std::vector<AlertBand>& bands, double range_m);

// Why the attitude `R` lies outside the envelope of `envelope_deg` around `R_nominal` (the
// angle between them and the envelope, in words); empty inside it or when envelope_deg is 0.
std::string OutsideAttitudeEnvelope(const Eigen::Matrix3d& R, const Eigen::Matrix3d& R_nominal,
                                    double envelope_deg);

// What one frame tells the monitor.
struct IntegrityInput {
  bool valid = false;  // a pose
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Zero();
  // The formation's nominal attitude, the centre of IntegrityOptions::attitude_envelope_deg.
  Eigen::Matrix3d R_tanker_receiver_nominal = Eigen::Matrix3d::Identity();
  bool tracking = false;  // a tracker made the pose; the fields below are meaningful
  TrackOutcome outcome = TrackOutcome::kMissed;
  // Every measurement this frame has (the registration, and the outline when it runs) was
  // accepted by the filter: the sensors agree with the track.
  bool agreeing = false;
  // [m^2, rad^2] how far off an acquisition can be: added to the covariance of a track not yet
  // confirmed, which may be a wrong one.
  Matrix6d acquisition_covariance = Matrix6d::Zero();
};

struct IntegrityResult {
  bool alert = true;
  std::string reason;  // why in alert; empty when not
  // The covariance to publish: the input's, with the acquisition's while unconfirmed.
  Matrix6d covariance = Matrix6d::Zero();
  ProtectionLevels levels;
  AlertBand limits;   // the phase's
  double risk = 0.0;  // per frame, that of the levels (IntegrityOptions::integrity_risk)
  int confirmed = 0;  // frames of agreement since the track started
};

// One per registrar: remembers how far the current track is confirmed. Not thread-safe.
class IntegrityMonitor {
 public:
  explicit IntegrityMonitor(const IntegrityOptions& options = {});  // validates

  IntegrityResult Assess(const IntegrityInput& in);

 private:
  // Counts the track's confirmation; the reason it is not yet confirmed, or empty.
  std::string Confirm(const IntegrityInput& in);

  IntegrityOptions options_;
  double k_;  // K(integrity_risk): a quantile, computed once
  int confirmed_ = 0;
};

}  // namespace aar_registration
