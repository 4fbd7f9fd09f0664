// A new track under watch (OutlineOptions::partial_below, partial_range_sigmas, range_all_starts):
// a partial start's poses withheld until confirmed, and a new track's range checked against
// stereo's points meanwhile.
#include <algorithm>
#include <sstream>

#include "aar_registration/range_check.h"
#include "aar_registration/registrar.h"

namespace aar_registration {

bool Registrar::ConfirmsNewTrack(const std::vector<Eigen::Vector3d>& sensed,
                                 const OutlineFrame* frame, RegistrarResult& out,
                                 std::string& range_note) {
  const OutlineOptions& o = options_.outline;
  const bool accepted = out.track.outcome == TrackOutcome::kAccepted;
  if (!(o.partial_range_sigmas > 0.0)) return accepted;
  if (!frame || !aligner_) return accepted;  // nothing to check with: the frames decide
  RangeCheckOptions options;
  options.sigmas = o.partial_range_sigmas;
  options.disparity_sigma = o.disparity_sigma;
  options.min_points = o.partial_range_min_points;
  options.independent_points = o.partial_range_independent_points;
  // Every rig's points (registration merges their clouds), on the first rig's left image: the
  // rigs see the receiver from nearly the same place far out.
  const RangeCheck check =
      CheckRange(sensed, aligner_->model(), frame->left_camera, frame->baseline(),
                 frame->boom_parts_in_tanker, out.track.filtered.T_tanker_receiver, options);
  range_note = check.ToString();
  if (check.enough && !check.agrees) {
    out.track = tracker_.Drop("a new track's range disagrees with stereo: " + range_note);
    if (out.outline_ran) out.outline_note = out.track.reason;
    out.valid = false;
    out.error = out.track.reason;
    return false;
  }
  if (!check.enough && o.partial_range_required) return false;  // not confirmed, not dropped
  return accepted;  // in range, or stereo has too few points to say: the frames decide
}

void Registrar::StartWatch(bool partial) {
  const OutlineOptions& o = options_.outline;
  watch_.partial = partial && o.partial_confirm > 0;
  watch_.range = o.partial_range_sigmas > 0.0 && (partial || o.range_all_starts);
  watch_.accepted = watch_.partial || watch_.range ? 0 : -1;
}

void Registrar::WatchNewTrack(const std::vector<Eigen::Vector3d>& sensed, const OutlineFrame* frame,
                              RegistrarResult& out) {
  if (watch_.accepted < 0) return;
  if (!out.tracking || tracker_.state() != TrackState::kTracking) {
    watch_.accepted = -1;  // lost: the next start decides again
    return;
  }
  std::string range_note;
  const bool confirms = watch_.range ? ConfirmsNewTrack(sensed, frame, out, range_note)
                                     : out.track.outcome == TrackOutcome::kAccepted;
  if (tracker_.state() != TrackState::kTracking) {
    watch_.accepted = -1;  // dropped by the range check
    return;
  }
  if (confirms)
    ++watch_.accepted;
  else if (out.track.outcome != TrackOutcome::kStarted &&
           out.track.outcome != TrackOutcome::kAccepted)
    watch_.accepted = 0;  // the agreement must be unbroken
  if (watch_.accepted >= std::max(1, options_.outline.partial_confirm)) {
    watch_.accepted = -1;
    return;
  }
  if (!watch_.partial || !out.valid) return;
  std::ostringstream s;
  s << "a start from a partial view (" << 100.0 * partial_share_
    << " % of the outline seen), not yet confirmed: " << watch_.accepted << " of "
    << options_.outline.partial_confirm << " frames accepted";
  if (!range_note.empty()) s << "; " << range_note;
  out.valid = false;
  out.error = s.str();
}

}  // namespace aar_registration
