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

// The rates' block of a new track (or one whose receiver maneuvered): the start's velocity
// sigmas, uncorrelated with anything.
void SetStartRates(const TrackerOptions& o, imm::Matrix12d& P) {
  P.block<6, 6>(6, 6).setZero();
  P.block<3, 3>(6, 6).diagonal().setConstant(o.initial_velocity_sigma * o.initial_velocity_sigma);
  P.block<3, 3>(9, 9).diagonal().setConstant(o.initial_angular_velocity_sigma *
                                             o.initial_angular_velocity_sigma);
}

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
  if (!(o.maneuver_acceleration_sigma >= 0.0))
    throw std::invalid_argument("tracker: maneuver_acceleration_sigma must be >= 0 (0: off)");
  if (o.maneuver_acceleration_sigma > 0.0 &&
      (!(o.maneuver_angular_acceleration_sigma > 0.0) || !(o.steady_sojourn_s > 0.0) ||
       !(o.maneuver_sojourn_s > 0.0)))
    throw std::invalid_argument(
        "tracker: with maneuvers, maneuver_angular_acceleration_sigma and the sojourns must be > "
        "0");
}

double Tracker::maneuver_probability() const {
  return state_ == TrackState::kTracking && models_.size() > 1 ? models_[1].probability : 0.0;
}

void Tracker::Reset() {
  state_ = TrackState::kAcquiring;
  rejections_ = 0;
  models_.clear();
  track_ = imm::Model{};
}

TrackUpdate Tracker::Drop(const std::string& reason) { return Lose(TrackOutcome::kLost, reason); }

void Tracker::Maneuver(double position_sigma, double rotation_sigma) {
  if (state_ != TrackState::kTracking) return;
  for (imm::Model& m : models_) {
    m.P.block<3, 3>(0, 0).diagonal().array() += position_sigma * position_sigma;
    m.P.block<3, 3>(3, 3).diagonal().array() += rotation_sigma * rotation_sigma;
    m.P.block<6, 6>(6, 0).setZero();
    m.P.block<6, 6>(0, 6).setZero();
    SetStartRates(options_, m.P);
  }
  track_ = imm::Combine(models_);
}

void Tracker::Propagate(double stamp_s, std::vector<imm::Model>& models) const {
  const double dt = stamp_s - stamp_s_;
  if (!(dt > 0.0)) return;
  imm::Mix(dt, models);
  for (imm::Model& m : models) {
    m.p = m.p + m.v * dt;
    m.R = Orthonormal(aar_geometry::RotationExp(m.w * dt) * m.R);
    imm::Matrix12d F = imm::Matrix12d::Identity();
    F.block<3, 3>(0, 6).diagonal().setConstant(dt);
    F.block<3, 3>(3, 9).diagonal().setConstant(dt);
    // Continuous white acceleration integrated over dt (composes exactly over several steps).
    imm::Matrix12d Q = imm::Matrix12d::Zero();
    const double qa = m.acceleration_sigma * m.acceleration_sigma;
    const double qw = m.angular_acceleration_sigma * m.angular_acceleration_sigma;
    for (int i = 0; i < 3; ++i) {
      for (const auto& [pose, rate, q] :
           {std::make_tuple(i, 6 + i, qa), std::make_tuple(3 + i, 9 + i, qw)}) {
        Q(pose, pose) = q * dt * dt * dt / 3.0;
        Q(pose, rate) = Q(rate, pose) = q * dt * dt / 2.0;
        Q(rate, rate) = q * dt;
      }
    }
    m.P = F * m.P * F.transpose() + Q;
  }
}

TrackPrediction Tracker::State(const imm::Model& m) const {
  TrackPrediction out;
  out.valid = state_ == TrackState::kTracking;
  out.T_tanker_receiver.linear() = m.R;
  out.T_tanker_receiver.translation() = m.p;
  out.covariance = m.P.topLeftCorner<6, 6>();
  out.velocity = m.v;
  out.angular_velocity = m.w;
  return out;
}

TrackPrediction Tracker::Predict(double stamp_s) const {
  // Nothing to predict while acquiring, past the coast limit or before the last frame (the
  // stamp went back: the next Update starts a new track).
  if (state_ != TrackState::kTracking || stamp_s - last_accept_s_ > options_.max_coast_s ||
      (has_stamp_ && stamp_s < last_frame_s_))
    return {};
  std::vector<imm::Model> models = models_;
  Propagate(stamp_s, models);
  return State(imm::Combine(models));
}

TrackUpdate Tracker::Lose(TrackOutcome outcome, const std::string& reason) {
  Reset();
  TrackUpdate u;
  u.outcome = outcome;
  u.reason = reason;
  return u;
}

TrackUpdate Tracker::Coast(double stamp_s, TrackOutcome outcome, const std::string& reason) {
  Propagate(stamp_s, models_);
  track_ = imm::Combine(models_);
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
    models_ = StartModels(p_m, R_m, covariance);
    track_ = imm::Combine(models_);
    stamp_s_ = last_accept_s_ = stamp_s;
    rejections_ = 0;
    TrackUpdate u;
    u.outcome = TrackOutcome::kStarted;
    u.reason = restart;
    u.filtered = Current();
    return u;
  }

  Propagate(stamp_s, models_);
  track_ = imm::Combine(models_);
  stamp_s_ = std::max(stamp_s_, stamp_s);
  Vector6d y;
  y << p_m - track_.p, Log(R_m * track_.R.transpose());
  const double d2 = y.dot((track_.P.topLeftCorner<6, 6>() + covariance).ldlt().solve(y));
  if (!(d2 <= options_.gate_chi2)) {
    std::ostringstream s;
    s << "registration " << y.head<3>().norm() << " m and " << y.tail<3>().norm() * kRadToDeg
      << " deg from the prediction (squared Mahalanobis distance " << d2 << " > "
      << options_.gate_chi2 << ")";
    TrackUpdate u = Coast(stamp_s, TrackOutcome::kRejected, s.str());
    u.mahalanobis2 = d2;
    return u;
  }
  std::vector<double> log_likelihoods;
  for (imm::Model& m : models_) log_likelihoods.push_back(UpdateModel(p_m, R_m, covariance, m));
  imm::Weigh(log_likelihoods, models_);
  track_ = imm::Combine(models_);
  if (!track_.P.allFinite() || !track_.p.allFinite() || !track_.R.allFinite() ||
      !track_.v.allFinite() || !track_.w.allFinite())
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

std::vector<imm::Model> Tracker::StartModels(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                             const Matrix6d& covariance) const {
  const TrackerOptions& o = options_;
  imm::Model m;
  m.p = p;
  m.R = R;
  m.P.topLeftCorner<6, 6>() = covariance;
  SetStartRates(o, m.P);
  m.acceleration_sigma = o.acceleration_sigma;
  m.angular_acceleration_sigma = o.angular_acceleration_sigma;
  if (!(o.maneuver_acceleration_sigma > 0.0)) return {m};
  // Each model at its share of time in the chain's steady state.
  const double total = o.steady_sojourn_s + o.maneuver_sojourn_s;
  m.sojourn_s = o.steady_sojourn_s;
  m.probability = o.steady_sojourn_s / total;
  imm::Model maneuvering = m;
  maneuvering.acceleration_sigma = o.maneuver_acceleration_sigma;
  maneuvering.angular_acceleration_sigma = o.maneuver_angular_acceleration_sigma;
  maneuvering.sojourn_s = o.maneuver_sojourn_s;
  maneuvering.probability = o.maneuver_sojourn_s / total;
  return {m, maneuvering};
}

double Tracker::UpdateModel(const Eigen::Vector3d& p_m, const Eigen::Matrix3d& R_m,
                            const Matrix6d& covariance, imm::Model& m) {
  Vector6d y;
  y << p_m - m.p, Log(R_m * m.R.transpose());
  const Matrix6d S = m.P.topLeftCorner<6, 6>() + covariance;
  const Eigen::LDLT<Matrix6d> S_ldlt(S);
  // K = P H^T S^-1 with H = [I6 0]; Joseph form keeps P symmetric positive definite.
  const Eigen::Matrix<double, 12, 6> K = S_ldlt.solve(m.P.leftCols<6>().transpose()).transpose();
  imm::Apply(K * y, m);
  imm::Matrix12d IKH = imm::Matrix12d::Identity();
  IKH.leftCols<6>() -= K;
  m.P = IKH * m.P * IKH.transpose() + K * covariance * K.transpose();
  m.P = 0.5 * (m.P + m.P.transpose()).eval();
  return -0.5 * (y.dot(S_ldlt.solve(y)) + S_ldlt.vectorD().array().abs().log().sum());
}

}  // namespace aar_registration
