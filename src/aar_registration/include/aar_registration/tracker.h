#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "aar_registration/imm.h"
#include "aar_registration/types.h"

namespace aar_registration {

// The receiver's motion relative to the tanker as a constant-velocity model over SE(3), filtered
// by an error-state Kalman filter. Pose errors are [position (tanker frame, m), rotation (tanker
// frame, rad)] with the rotation error left-multiplied: R_true = Exp(dtheta) * R_estimate.
// With maneuver_acceleration_sigma > 0, an interacting-multiple-model filter (imm.h): the steady
// model beside a maneuvering one with that white acceleration, mixed every frame and weighed by
// how well each predicted the measurements; the published state and covariance are their
// mixture, so that a maneuver's first frames widen the covariance (and the protection levels)
// as the maneuvering model gains weight, and the velocity follows within a few frames.
struct TrackerOptions {
  // Process noise: white acceleration, per axis. A receiver closing on a tanker changes its
  // closure rate by tenths of a m/s per second and its attitude rate by about a degree per
  // second per second.
  double acceleration_sigma = 0.5;           // [m/s^2]
  double angular_acceleration_sigma = 0.02;  // [rad/s^2]
  // The velocity prior when a track starts from one registration (the receiver's closure rate,
  // a few m/s, is not known yet).
  double initial_velocity_sigma = 3.0;          // [m/s]
  double initial_angular_velocity_sigma = 0.1;  // [rad/s]
  // Innovation gate: a registration whose squared Mahalanobis distance to the prediction exceeds
  // this is rejected. 22.46 is the chi-square 99.9% point for 6 degrees of freedom.
  double gate_chi2 = 22.46;
  // After this many rejected or missing registrations in a row the track is dropped and the next
  // registration starts a new one (acquisition).
  int max_rejections = 5;
  // A prediction further than this past the last accepted registration is not trusted [s].
  double max_coast_s = 1.0;
  // Maneuvers (ours): the maneuvering model's white acceleration; 0: one model (the filter
  // above alone, as the thesis's experiments and tracking* fly).
  double maneuver_acceleration_sigma = 0.0;          // [m/s^2]
  double maneuver_angular_acceleration_sigma = 0.1;  // [rad/s^2]
  // Mean time in each model before a switch: the Markov chain's rates (per second, so that the
  // filter is the same at any frame rate).
  double steady_sojourn_s = 20.0;   // [s]
  double maneuver_sojourn_s = 3.0;  // [s]
};

enum class TrackState {
  kAcquiring,  // no track: the next registration starts one
  kTracking,   // a track, updated at most max_rejections frames ago
};

// What one registration did to the track.
enum class TrackOutcome {
  kStarted,   // it started a new track (acquisition)
  kAccepted,  // it passed the gate and updated the track
  kRejected,  // it failed the gate; the track coasts on the prediction
  kMissed,    // no registration this frame; the track coasts
  kLost,      // rejections or coasting ran out, or the filter broke: back to acquisition
  kReset,     // the stamp went backwards (a bag loop): back to acquisition
};

const char* ToString(TrackOutcome outcome);

struct TrackPrediction {
  bool valid = false;  // false while acquiring or past max_coast_s
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Zero();  // [m^2, rad^2] position then rotation, tanker frame
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          // [m/s] tanker frame
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // [rad/s] tanker frame
};

struct TrackUpdate {
  TrackOutcome outcome = TrackOutcome::kMissed;
  double mahalanobis2 = 0.0;  // the innovation's squared Mahalanobis distance (0 if not gated)
  std::string reason;         // why a registration was rejected or the track lost/reset
  TrackPrediction filtered;   // the track after this frame (invalid after kLost/kReset)
};

// Tracks one receiver. Stamps are seconds on any monotonic clock (message stamps). Not
// thread-safe.
class Tracker {
 public:
  explicit Tracker(const TrackerOptions& options = {});  // throws std::invalid_argument

  TrackState state() const { return state_; }
  int rejections() const { return rejections_; }
  // The maneuvering model's probability (0 with one model or while acquiring).
  double maneuver_probability() const;

  // The pose predicted at `stamp_s`, with its covariance; invalid while acquiring, past
  // max_coast_s and before the last frame's stamp. The filter is not changed.
  TrackPrediction Predict(double stamp_s) const;

  // Folds in a registration at `stamp_s`: T_tanker_receiver with its 6x6 covariance (position,
  // rotation; tanker frame). A non-finite pose or covariance counts as a miss.
  TrackUpdate Update(double stamp_s, const Eigen::Isometry3d& T_tanker_receiver,
                     const Matrix6d& covariance);
  // A frame at `stamp_s` without a registration (kMissed), or with one that failed a check
  // before the tracker's gate (kRejected, with `reason`).
  TrackUpdate Miss(double stamp_s);
  TrackUpdate Reject(double stamp_s, const std::string& reason);

  // Back to acquisition.
  void Reset();
  // Back to acquisition with a reason (kLost): a check outside the filter found the track wrong.
  TrackUpdate Drop(const std::string& reason);
  // The receiver maneuvered: its velocities are uncertain again (the start's sigmas) and the
  // pose's covariance grows by `position_sigma` [m] and `rotation_sigma` [rad] per axis, so that
  // the next update may move the track far.
  void Maneuver(double position_sigma, double rotation_sigma);

 private:
  // Mixes the models and moves each to `stamp_s` (no-op for dt <= 0).
  void Propagate(double stamp_s, std::vector<imm::Model>& models) const;
  // One model's Kalman update; returns its measurement's log-likelihood (up to a constant).
  static double UpdateModel(const Eigen::Vector3d& p_m, const Eigen::Matrix3d& R_m,
                            const Matrix6d& covariance, imm::Model& m);
  // The models at a start: the measurement, no velocity, the start's velocity sigmas.
  std::vector<imm::Model> StartModels(const Eigen::Vector3d& p, const Eigen::Matrix3d& R,
                                      const Matrix6d& covariance) const;
  TrackUpdate Coast(double stamp_s, TrackOutcome outcome, const std::string& reason);
  TrackUpdate Lose(TrackOutcome outcome, const std::string& reason);
  TrackPrediction Current() const { return State(track_); }
  TrackPrediction State(const imm::Model& m) const;
  // Loses the track when the stamp went back; otherwise notes the frame. True: reset.
  bool CheckStamp(double stamp_s, TrackUpdate* update);
  TrackUpdate NoRegistration(double stamp_s, TrackOutcome outcome, const std::string& reason);

  TrackerOptions options_;
  TrackState state_ = TrackState::kAcquiring;
  double stamp_s_ = 0.0;  // of the state below
  double last_accept_s_ = 0.0;
  bool has_stamp_ = false;  // any frame seen (for the backwards-stamp check)
  double last_frame_s_ = 0.0;
  int rejections_ = 0;
  std::vector<imm::Model> models_;  // steady, then (with maneuvers) maneuvering
  imm::Model track_;                // their mixture: what the tracker publishes
};

}  // namespace aar_registration
