#include "aar_registration/tracker.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <aar_geometry/pose.h>

namespace aar_registration {
namespace {

Eigen::Vector3d Log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Keeps R a rotation after many small products.
Eigen::Matrix3d Orthonormal(const Eigen::Matrix3d& R) {
  return Eigen::Quaterniond(R).normalized().toRotationMatrix();
}

constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

const char* ToString(TrackOutcome outcome) {
  static const char* const kNames[] = {"started", "accepted", "rejected",
                                       "missed",  "lost",     "reset"};  // in the enum's order
  const auto i = static_cast<size_t>(outcome);
  return i < sizeof(kNames) / sizeof(kNames[0]) ? kNames[i] : "?";
}

Tracker::Tracker(const TrackerOptions& options) : options_(options) {
  const TrackerOptions& o = options_;
  if (!(o.acceleration_sigma > 0.0) || !(o.angular_acceleration_sigma > 0.0) ||
      !(o.initial_velocity_sigma > 0.0) || !(o.initial_angular_velocity_sigma > 0.0))
    throw std::invalid_argument("tracker: the noise sigmas must be > 0");
  if (!(o.gate_chi2 > 0.0)) throw std::invalid_argument("tracker: gate_chi2 must be > 0");
  if (o.max_rejections < 1) throw std::invalid_argument("tracker: max_rejections must be >= 1");
  if (!(o.max_coast_s > 0.0)) throw std::invalid_argument("tracker: max_coast_s must be > 0");
}

void Tracker::Reset() {
  state_ = TrackState::kAcquiring;
  rejections_ = 0;
  v_.setZero();
  w_.setZero();
  P_.setZero();
}

TrackUpdate Tracker::Drop(const std::string& reason) { return Lose(TrackOutcome::kLost, reason); }

void Tracker::Maneuver(double position_sigma, double rotation_sigma) {
  if (state_ != TrackState::kTracking) return;
  P_.block<3, 3>(0, 0).diagonal().array() += position_sigma * position_sigma;
  P_.block<3, 3>(3, 3).diagonal().array() += rotation_sigma * rotation_sigma;
  P_.block<6, 6>(6, 0).setZero();
  P_.block<6, 6>(0, 6).setZero();
  P_.block<6, 6>(6, 6).setZero();
  P_.block<3, 3>(6, 6).diagonal().setConstant(options_.initial_velocity_sigma *
                                              options_.initial_velocity_sigma);
  P_.block<3, 3>(9, 9).diagonal().setConstant(options_.initial_angular_velocity_sigma *
                                              options_.initial_angular_velocity_sigma);
}

void Tracker::Propagate(double stamp_s, Eigen::Vector3d& p, Eigen::Matrix3d& R,
                        Matrix12d& P) const {
  const double dt = stamp_s - stamp_s_;
  if (!(dt > 0.0)) return;
  p = p + v_ * dt;
  R = Orthonormal(aar_geometry::RotationExp(w_ * dt) * R);
  Matrix12d F = Matrix12d::Identity();
  F.block<3, 3>(0, 6).diagonal().setConstant(dt);
  F.block<3, 3>(3, 9).diagonal().setConstant(dt);
  // Continuous white acceleration integrated over dt (composes exactly over several steps).
  Matrix12d Q = Matrix12d::Zero();
  const double qa = options_.acceleration_sigma * options_.acceleration_sigma;
  const double qw = options_.angular_acceleration_sigma * options_.angular_acceleration_sigma;
  for (int i = 0; i < 3; ++i) {
    for (const auto& [pose, rate, q] :
         {std::make_tuple(i, 6 + i, qa), std::make_tuple(3 + i, 9 + i, qw)}) {
      Q(pose, pose) = q * dt * dt * dt / 3.0;
      Q(pose, rate) = Q(rate, pose) = q * dt * dt / 2.0;
      Q(rate, rate) = q * dt;
    }
  }
  P = F * P * F.transpose() + Q;
}

TrackPrediction Tracker::State(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                               const Matrix12d& P) const {
  TrackPrediction out;
  out.valid = state_ == TrackState::kTracking;
  out.T_tanker_receiver.linear() = R;
  out.T_tanker_receiver.translation() = p;
  out.covariance = P.topLeftCorner<6, 6>();
  out.velocity = v_;
  out.angular_velocity = w_;
  return out;
}

TrackPrediction Tracker::Predict(double stamp_s) const {
  // Nothing to predict while acquiring, past the coast limit or before the last frame (the
  // stamp went back: the next Update starts a new track).
  if (state_ != TrackState::kTracking || stamp_s - last_accept_s_ > options_.max_coast_s ||
      (has_stamp_ && stamp_s < last_frame_s_))
    return {};
  Eigen::Vector3d p = p_;
  Eigen::Matrix3d R = R_;
  Matrix12d P = P_;
  Propagate(stamp_s, p, R, P);
  return State(p, R, P);
}

TrackUpdate Tracker::Lose(TrackOutcome outcome, const std::string& reason) {
  Reset();
  TrackUpdate u;
  u.outcome = outcome;
  u.reason = reason;
  return u;
}

TrackUpdate Tracker::Coast(double stamp_s, TrackOutcome outcome, const std::string& reason) {
  Propagate(stamp_s, p_, R_, P_);
  stamp_s_ = std::max(stamp_s_, stamp_s);
  ++rejections_;
  if (rejections_ >= options_.max_rejections) {
    return Lose(TrackOutcome::kLost, reason + "; " + std::to_string(rejections_) +
                                         " frames in a row without an accepted registration");
  }
  if (stamp_s - last_accept_s_ > options_.max_coast_s) {
    std::ostringstream s;
    s << reason << "; no accepted registration for " << stamp_s - last_accept_s_ << " s";
    return Lose(TrackOutcome::kLost, s.str());
  }
  TrackUpdate u;
  u.outcome = outcome;
  u.reason = reason;
  u.filtered = Current();
  return u;
}

bool Tracker::CheckStamp(double stamp_s, TrackUpdate* update) {
  if (has_stamp_ && stamp_s < last_frame_s_) {
    std::ostringstream s;
    s << "stamp went back by " << last_frame_s_ - stamp_s << " s";
    last_frame_s_ = stamp_s;
    *update = Lose(TrackOutcome::kReset, s.str());
    return true;
  }
  has_stamp_ = true;
  last_frame_s_ = stamp_s;
  return false;
}

TrackUpdate Tracker::NoRegistration(double stamp_s, TrackOutcome outcome,
                                    const std::string& reason) {
  TrackUpdate u;
  u.reason = reason;
  if (!std::isfinite(stamp_s)) return u;
  if (CheckStamp(stamp_s, &u)) return u;
  if (state_ != TrackState::kTracking) return u;
  return Coast(stamp_s, outcome, reason);
}

TrackUpdate Tracker::Miss(double stamp_s) {
  return NoRegistration(stamp_s, TrackOutcome::kMissed, "no registration");
}

TrackUpdate Tracker::Reject(double stamp_s, const std::string& reason) {
  return NoRegistration(stamp_s, TrackOutcome::kRejected, reason);
}

TrackUpdate Tracker::Update(double stamp_s, const Eigen::Isometry3d& T_tanker_receiver,
                            const Matrix6d& covariance) {
  if (!T_tanker_receiver.matrix().allFinite() || !covariance.allFinite() || !std::isfinite(stamp_s))
    return Reject(stamp_s, "registration not finite");
  std::string restart;
  if (has_stamp_ && stamp_s < last_frame_s_) {
    std::ostringstream s;
    s << "stamp went back by " << last_frame_s_ - stamp_s << " s: new track";
    restart = s.str();
    Reset();
  } else if (state_ == TrackState::kTracking && stamp_s - last_accept_s_ > options_.max_coast_s) {
    std::ostringstream s;
    s << "no accepted registration for " << stamp_s - last_accept_s_ << " s: new track";
    restart = s.str();
    Reset();
  }
  has_stamp_ = true;
  last_frame_s_ = stamp_s;

  const Eigen::Vector3d p_m = T_tanker_receiver.translation();
  const Eigen::Matrix3d R_m = Orthonormal(T_tanker_receiver.linear());
  if (state_ != TrackState::kTracking) {
    state_ = TrackState::kTracking;
    p_ = p_m;
    R_ = R_m;
    v_.setZero();
    w_.setZero();
    P_.setZero();
    P_.topLeftCorner<6, 6>() = covariance;
    P_.block<3, 3>(6, 6).diagonal().setConstant(options_.initial_velocity_sigma *
                                                options_.initial_velocity_sigma);
    P_.block<3, 3>(9, 9).diagonal().setConstant(options_.initial_angular_velocity_sigma *
                                                options_.initial_angular_velocity_sigma);
    stamp_s_ = last_accept_s_ = stamp_s;
    rejections_ = 0;
    TrackUpdate u;
    u.outcome = TrackOutcome::kStarted;
    u.reason = restart;
    u.filtered = Current();
    return u;
  }

  Propagate(stamp_s, p_, R_, P_);
  stamp_s_ = std::max(stamp_s_, stamp_s);
  Vector6d y;
  y << p_m - p_, Log(R_m * R_.transpose());
  const Matrix6d S = P_.topLeftCorner<6, 6>() + covariance;
  const Eigen::LDLT<Matrix6d> S_ldlt(S);
  const double d2 = y.dot(S_ldlt.solve(y));
  if (!(d2 <= options_.gate_chi2)) {
    std::ostringstream s;
    s << "registration " << y.head<3>().norm() << " m and " << y.tail<3>().norm() * kRadToDeg
      << " deg from the prediction (squared Mahalanobis distance " << d2 << " > "
      << options_.gate_chi2 << ")";
    TrackUpdate u = Coast(stamp_s, TrackOutcome::kRejected, s.str());
    u.mahalanobis2 = d2;
    return u;
  }
  // K = P H^T S^-1 with H = [I6 0]; Joseph form keeps P symmetric positive definite.
  const Eigen::Matrix<double, 12, 6> K = S_ldlt.solve(P_.leftCols<6>().transpose()).transpose();
  const Eigen::Matrix<double, 12, 1> dx = K * y;
  p_ += dx.segment<3>(0);
  R_ = Orthonormal(aar_geometry::RotationExp(dx.segment<3>(3)) * R_);
  v_ += dx.segment<3>(6);
  w_ += dx.segment<3>(9);
  Matrix12d IKH = Matrix12d::Identity();
  IKH.leftCols<6>() -= K;
  P_ = IKH * P_ * IKH.transpose() + K * covariance * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  if (!P_.allFinite() || !p_.allFinite() || !R_.allFinite() || !v_.allFinite() || !w_.allFinite())
    return Lose(TrackOutcome::kLost, "filter diverged (state not finite)");
  rejections_ = 0;
  last_accept_s_ = stamp_s;
  TrackUpdate u;
  u.outcome = TrackOutcome::kAccepted;
  u.mahalanobis2 = d2;
  u.reason = restart;
  u.filtered = Current();
  return u;
}

}  // namespace aar_registration
