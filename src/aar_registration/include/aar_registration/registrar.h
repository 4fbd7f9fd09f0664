#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <memory>

#include <aar_alignment/acquire.h>
#include <aar_alignment/aligner.h>
#include <aar_geometry/receiver_reference.h>
#include <aar_geometry/triangle_mesh.h>
#include <Eigen/Geometry>

#include "aar_registration/icp.h"
#include "aar_registration/integrity.h"
#include "aar_registration/tracker.h"

namespace aar_registration {

// The reference model registered to: a static one built once from the receiver mesh (thesis:
// shelled, or its wings and nose), or one given per frame (the occlusion stage's dynamic model).
enum class ReferenceKind { kShelled, kWingsNose, kDense, kTopic };
// Thesis: centroid of the sensed points with the tanker's orientation; or the previous estimate;
// or the tracker's prediction at the frame's stamp (the centroid while acquiring).
enum class SeedMode { kCentroid, kPrevious, kPrediction };
using aar_geometry::SeedPoints;  // which sensed points the centroid seed takes

// A registration the tracker is not even asked about: too loose a fit to be a pose. Loose
// defaults: far out (region A) the RMS of good registrations reaches half a metre (stereo
// fattening at the silhouettes); the tracker's innovation gate does the fine rejection.
struct RegistrationGate {
  double min_fitness = 0.1;  // share of sensed points matched within max_correspondence_distance
  double max_rms = 0.7;      // [m] of the matched pairs
};

// The receiver's outline in both images as a second measurement of the tracker (issue 27; not in
// the thesis): aligned from the prediction each frame and fused beside ICP with its own
// covariance, so that the weights follow range; a start must fit the images, a track whose
// outline stops fitting is dropped, and a registration the gate rejects but whose outline fits is
// a maneuver. Needs tracking and the frame's images (Registrar::Register's `outline`).
struct OutlineOptions {
  bool enabled = false;
  aar_alignment::AlignmentOptions alignment;
  // An alignment whose fit (AlignmentResult::quality) is below this is not fused; a start below
  // it is refused.
  double min_quality = 0.5;
  // This many frames in a row without a fitting outline while tracking: the track is dropped
  // (an integrity loss) and acquired again.
  int max_poor_frames = 5;
  // While acquiring, a start whose registration fails the gate or whose outline does not fit is
  // tried again from the densest ball of the points outside the refused registration's (clutter
  // such as the boom's leftover points can be denser than a far receiver), up to this many seeds
  // per frame; 1: the seed only.
  int start_candidates = 3;
  // When every stereo seed is refused, a start from the images alone (aar_alignment::Acquire):
  // the receiver's silhouette at the nominal attitude searched over the left image at the
  // acquisition's ranges (around stereo's points in that range, acquisition.cue_min_points); a fit
  // of at least image_start_quality, with acquisition.min_visible of the outline seen, starts the
  // track. For far out, where stereo gives a receiver a few dozen points that culling or the boom's
  // own points can outweigh.
  bool image_start = false;
  aar_alignment::AcquisitionOptions acquisition;
  double image_start_quality = 0.7;
  // A start from the images alone that sees less than partial_below of its outline
  // (aar_alignment::SeenShare) is a partial one: the track runs, but its poses are not
  // published until partial_confirm frames in a row after the start had a measurement accepted
  // (a wrong start from a few lines is rejected by the next frames' measurements and dropped
  // unseen). partial_below 0: no start is partial; 1: every start from the images is.
  double partial_below = 0.0;
  int partial_confirm = 2;
  // A partial start's range checked against stereo's points (RangeCheck) on every frame until it
  // is confirmed: a frame where the median depth of stereo's points on the receiver's image lies
  // outside partial_range_sigmas sigma_Z (disparity_sigma) of the receiver's depth drops the
  // track. With fewer than partial_range_min_points such points stereo cannot say (at 150 m,
  // where the boom hides most of the receiver from one camera, it gives none): the frame counts
  // as without the check. 0: off.
  double partial_range_sigmas = 0.0;
  int partial_range_min_points = 10;
  // How many of those points count as independent (RangeCheckOptions::independent_points).
  int partial_range_independent_points = 1;
  // A frame without a verdict (too few points) does not confirm a start under watch: its poses
  // stay withheld until stereo's range agrees (a wrong start over the background has no points).
  bool partial_range_required = false;
  // The same range check on every new track until partial_confirm frames are accepted, whether
  // it started from stereo's seeds or the whole outline; its poses are published meanwhile.
  bool range_all_starts = false;
  // The prior of an alignment from an ICP pose (a start, or a maneuver's registration).
  double start_sigma_position = 2.0;   // [m]
  double start_sigma_rotation = 0.05;  // [rad]
  // A registration the tracker's gate rejects whose outline, aligned from it, fits at least this
  // well: the receiver maneuvered; the track follows it (velocity uncertainty reset).
  double maneuver_quality = 0.7;
  // Stereo's range noise in ICP's covariance: sigma_Z = Z^2 sigma_d / (f b) of each point, along
  // the left camera's ray to the receiver, over the independent correspondences (IcpOptions).
  // [px]; 0: off (ICP's covariance from its residuals only).
  double disparity_sigma = 0.0;
  // The same range noise also turns the receiver about the axes across the ray (points at lever
  // arm l across it move by l dtheta in range): added to ICP's rotation covariance. Far out ICP's
  // own covariance, from residuals its correspondence distance cuts short, claims a degree where
  // the noise allows several (docs/INTEGRITY.md). Needs disparity_sigma.
  bool disparity_rotation = false;
  // [1/m^2, 1/rad^2] added to the alignment's information before it is inverted into a
  // measurement covariance: directions the outline does not see get no weight.
  double information_floor_position = 1e-4;
  double information_floor_rotation = 1e-2;
  // The alignment from the track's prediction is the prediction's prior and the images' data
  // combined (its pose is the posterior's); fused as it is, the filter counts that prior twice,
  // lags a maneuver and believes itself. With this, the pose fused is the images' own (the
  // prior taken out, covariance_models.h DataOnlyMeasurement).
  bool remove_prior = false;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A further stereo rig's rectified mono8 pair and its cameras in the tanker frame (issue 44).
struct RigImages {
  cv::Mat left, right;
  aar_alignment::PinholeCamera left_camera, right_camera;
};

// One frame's images for the outline: rectified mono8 pair, their cameras in the tanker frame,
// the boom's convex parts (vertices in the tanker frame) to mask out.
struct OutlineFrame {
  cv::Mat left, right;
  aar_alignment::PinholeCamera left_camera, right_camera;
  std::vector<std::vector<Eigen::Vector3d>> boom_parts_in_tanker;
  // Further rigs' rectified pairs and cameras in the tanker frame, in rig order: the outline is
  // aligned (and searched for, at an image start) in their images too. Empty: one rig. The range
  // noise and range checks (disparity_sigma, persistent_error, partial_range_sigmas) keep using
  // the first rig's cameras above: the rigs are a few metres apart, far less than the range.
  std::vector<RigImages> more_rigs;

  double baseline() const {  // [m] between the two cameras
    return (right_camera.T_tanker_optical.translation() -
            left_camera.T_tanker_optical.translation())
        .norm();
  }
};

// Image errors that persist from frame to frame (a silhouette's edges found a fraction of a pixel
// out or in for seconds as the view changes slowly: blur, texture behind the receiver, stereo's
// fattening). The filter averages frames as if their errors were independent, so its covariance
// shrinks below what these allow; the published covariance adds them back (docs/INTEGRITY.md):
// the receiver's apparent size off by pixel_sigma puts it Z^2 pixel_sigma / (f W) off in range
// (W the receiver's size) and one end against the other turns it by pixel_sigma Z / (f W). A
// shift of both edges together (across the line of sight) is not modelled: measured, it is a
// third to a fifth of the size's. Needs the frame's cameras (the outline's).
struct PersistentErrorOptions {
  double pixel_sigma = 0.0;  // [px]; 0: off (the filter's covariance as it is)
};

struct RegistrarOptions {
  ReferenceKind reference = ReferenceKind::kShelled;
  aar_geometry::ReferenceModelOptions sampling;
  Eigen::Isometry3d T_tanker_receiver_nominal = Eigen::Isometry3d::Identity();  // shelling pose
  // The parts of the static "wings and nose" reference (a receiver description's static_parts).
  std::vector<std::string> static_parts = {"left_wing", "right_wing", "nose"};
  IcpOptions icp;
  SeedMode seed = SeedMode::kCentroid;
  SeedPoints seed_points = SeedPoints::kAll;  // of the centroid seed (also while acquiring)
  double previous_max_age = 1.0;              // [s] older previous estimates are not used as seeds
  // Registers at most this many sensed points, a random subset drawn with subsample_seed on each
  // frame (0: all, the thesis).
  int max_sensed_points = 0;
  unsigned subsample_seed = 1;
  // A bound on the work of one frame whatever arrives: a larger cloud is registered as a random
  // subset of this many points (ungated ICP costs about 35 us per point on 2 cores, so a cloud of
  // 2 million points would take 70 s). Near contact the default approach gives about 13,000.
  // 0: no bound.
  int max_cloud_points = 50000;
  // Tracking (not in the thesis): registrations filtered by a constant-velocity model; the
  // result is the filtered pose with its covariance, and frames whose registration is missing
  // or fails `gate` or the tracker's innovation gate coast on the prediction.
  bool track = false;
  TrackerOptions tracker;
  RegistrationGate gate;
  OutlineOptions outline;
  PersistentErrorOptions persistent_error;
  // Protection levels and alerts on every pose (docs/INTEGRITY.md).
  IntegrityOptions integrity;
  // Fault injection, for the integrity tests only: every new track starts this much further
  // from the tanker's origin [m] than its acquisition found (a deliberately wrong start; 0: off).
  double fault_start_offset_m = 0.0;
};

struct RegistrarResult {
  bool valid = false;  // a pose; otherwise `error` says why not (a miss)
  std::string error;
  // The estimate: the registration, or with tracking the filtered pose (the prediction on
  // frames that coast).
  Eigen::Isometry3d T_tanker_receiver = Eigen::Isometry3d::Identity();
  // [m^2, rad^2] of T_tanker_receiver: position then rotation (left perturbation), tanker frame.
  // ICP's covariance, or the filter's with tracking.
  Matrix6d covariance = Matrix6d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          // [m/s] tanker frame (tracking)
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // [rad/s] tanker frame (tracking)
  bool registered = false;  // ICP ran and found a pose (T_tanker_receiver_registered)
  Eigen::Isometry3d T_tanker_receiver_registered = Eigen::Isometry3d::Identity();
  SeedMode seed = SeedMode::kCentroid;  // where this frame's ICP started
  bool tracking = false;                // options.track: `track` below is meaningful
  TrackUpdate track;                    // outcome, reason, squared Mahalanobis distance
  RegistrationResult icp;               // converged, iterations, rms, fitness, correspondences
  size_t sensed_points = 0;             // registered (finite, in the tanker frame, subsampled)
  size_t cut_from_points = 0;           // the cloud's size when max_cloud_points cut it; else 0
  size_t reference_points = 0;
  double registration_ms = 0.0;  // [ms] seeding, subsampling, ICP and the filter
  // The outline (options.outline): its last alignment this frame, whether it entered the filter,
  // and what it decided (start refused, maneuver, integrity loss, not fused and why).
  bool outline_ran = false;
  aar_alignment::AlignmentResult outline;
  bool outline_fused = false;
  std::string outline_note;
  double outline_ms = 0.0;  // [ms] of registration_ms
  // With tracking: this frame's registration entered the filter (passed both gates).
  bool registration_fused = false;
  // The pose's protection levels, the phase's alert limits and whether it is in alert.
  IntegrityResult integrity;
};

// ICP's covariance (RegistrationResult::covariance of T_receiver_tanker, receiver frame) as the
// covariance of T_tanker_receiver: position then rotation, left perturbation, tanker frame.
Matrix6d CovarianceInTanker(const Matrix6d& icp_covariance,
                            const Eigen::Isometry3d& T_tanker_receiver);

// Registers each sensed cloud against the receiver's reference model: owns the reference, the
// seed policy (centroid, previous estimate or prediction), ICP and, when tracking, the tracker.
// One per node; not thread-safe.
class Registrar {
 public:
  explicit Registrar(const RegistrarOptions& options);  // throws std::invalid_argument

  // The static reference (options.reference other than kTopic): `receiver` sampled, then shelled
  // as seen from `eyes_in_tanker` (the cameras) at the nominal pose unless kDense. Returns its
  // size. Throws std::runtime_error when fewer than 100 points remain.
  size_t BuildStaticReference(const aar_geometry::TriangleMesh& receiver,
                              const std::vector<Eigen::Vector3d>& eyes_in_tanker);

  // This frame's reference (receiver frame), normals optional (point-to-plane needs them).
  // Throws std::invalid_argument for fewer than 10 points or a target ICP refuses; the previous
  // reference is gone either way, so a frame never registers to a stale one. A reference equal to
  // the current one (the boom hides nothing new) keeps its k-d tree: returns false then.
  bool SetReference(std::vector<Eigen::Vector3d> points, std::vector<Eigen::Vector3d> normals);
  bool has_reference() const { return icp_.has_target(); }

  // The receiver mesh for the outline (options.outline.enabled); throws std::invalid_argument
  // for a bad mesh.
  void SetOutlineModel(const aar_geometry::TriangleMesh& receiver);
  bool has_outline_model() const { return aligner_ != nullptr; }

  // Sensed points in the tanker frame at `stamp_s` [s], and the frame's images for the outline
  // (null: none this frame). `left_eye_in_tanker`: the camera the points were measured from
  // (IcpMetric::kStereoRays needs it; a frame without it has no pose). Never throws: a frame
  // without a pose comes back with valid = false and the reason.
  RegistrarResult Register(const std::vector<Eigen::Vector3d>& sensed_in_tanker, double stamp_s,
                           const OutlineFrame* outline = nullptr,
                           const Eigen::Vector3d* left_eye_in_tanker = nullptr);

  // The tracker's pose at `stamp_s` (invalid when not tracking or acquiring), for the stages
  // before registration (the occlusion stage's predicted pose, stereo's region of interest).
  TrackPrediction Predict(double stamp_s) const;

  const RegistrarOptions& options() const { return options_; }

 private:
  // Registration alone: fills out.icp, out.registered and out.T_tanker_receiver_registered;
  // throws with the reason when there is no pose.
  void Align(const std::vector<Eigen::Vector3d>& sensed, const Eigen::Isometry3d& seed,
             RegistrarResult& out) const;

  // The tracking half of Register: ICP's pose (gated) and the outline into the tracker.
  void Track(double stamp_s, const std::vector<Eigen::Vector3d>& sensed, const OutlineFrame* frame,
             RegistrarResult& out);
  // Acquiring with the outline: the first of outline.start_candidates seeds whose registration
  // passes the gate and whose outline fits starts the track; otherwise the frame is rejected.
  void Start(double stamp_s, const std::vector<Eigen::Vector3d>& sensed, const OutlineFrame& frame,
             RegistrarResult& out);
  // The start from the images alone (outline.image_start), `sensed` its cue
  // (acquisition.cue_min_points); false and why not when it fits too poorly.
  bool ImageStart(double stamp_s, const std::vector<Eigen::Vector3d>& sensed,
                  const OutlineFrame& frame, RegistrarResult& out, std::string& why);
  // Why the registration in `out` fails the gate (fitness, RMS, degenerate); empty: it passes.
  std::string GateFailure(const RegistrarResult& out) const;
  // The outline aligned from `T` with its covariance; fills out.outline*.
  aar_alignment::AlignmentResult AlignOutline(const OutlineFrame& frame, const Eigen::Isometry3d& T,
                                              const Matrix6d& covariance,
                                              RegistrarResult& out) const;
  Matrix6d StartCovariance() const;
  // A start's pose as the tracker takes it: `T`, or moved by fault_start_offset_m.
  Eigen::Isometry3d StartPose(const Eigen::Isometry3d& T) const;
  // ICP's covariance in the tanker frame, with stereo's range noise when asked for.
  Matrix6d IcpCovariance(const RegistrarResult& out, const OutlineFrame* frame) const;
  // The covariance of the errors that persist across frames at pose `T` (PersistentErrorOptions);
  // zero without the frame's cameras or the receiver's size.
  Matrix6d PersistentCovariance(const Eigen::Isometry3d& T, const OutlineFrame* frame) const;
  // Why `T`'s attitude is outside the formation's envelope (integrity.attitude_envelope_deg
  // around T_tanker_receiver_nominal); empty inside it or with the envelope off.
  std::string OutsideEnvelope(const Eigen::Isometry3d& T) const;
  // A track whose filtered attitude left the envelope is dropped (kLost, back to acquisition).
  void DropOutsideEnvelope(RegistrarResult& out);
  // The frame's integrity from its pose, covariance and what the tracker did; an unconfirmed
  // track's covariance gains the start's (StartCovariance: how far off an acquisition can be).
  void AssessIntegrity(RegistrarResult& out);
  // A new track under watch (a partial start, or any start with range_all_starts): its range
  // checked against stereo's points (partial_range_sigmas) and a partial start's poses withheld
  // (out.valid false and why) until partial_confirm frames in a row are accepted.
  void StartWatch(bool partial);  // at a start: what to watch
  void WatchNewTrack(const std::vector<Eigen::Vector3d>& sensed, const OutlineFrame* frame,
                     RegistrarResult& out);  // each frame
  // Whether this frame confirms a watched start: accepted, and not out of range (stereo's points
  // agree, or are too few to say, or there are no images to check with). Drops the track
  // (out.track) when stereo's range disagrees; `range_note` gets the check's figures
  // (RangeCheck::ToString).
  bool ConfirmsNewTrack(const std::vector<Eigen::Vector3d>& sensed, const OutlineFrame* frame,
                        RegistrarResult& out, std::string& range_note);

  RegistrarOptions options_;
  Icp icp_;
  std::unique_ptr<aar_alignment::OutlineAligner> aligner_;
  int poor_outline_frames_ = 0;
  struct Watch {
    int accepted = -1;     // frames accepted in a row since the start; -1: no track under watch
    bool partial = false;  // a partial start: poses withheld until confirmed
    bool range = false;    // its range checked against stereo's points
  } watch_;
  double partial_share_ = 0.0;                     // the share of its outline the partial start saw
  std::vector<Eigen::Vector3d> reference_points_;  // receiver frame
  std::vector<Eigen::Vector3d> reference_normals_;                // SetReference's, if any
  std::optional<std::pair<double, Eigen::Isometry3d>> previous_;  // stamp [s], T_tanker_receiver
  std::optional<Eigen::Vector3d> eye_;  // this frame's left camera, tanker frame (Register's)
  Tracker tracker_;
  IntegrityMonitor integrity_;
  double receiver_size_m_ = 0.0;  // the outline model's bounding-box diagonal [m]
};

}  // namespace aar_registration
