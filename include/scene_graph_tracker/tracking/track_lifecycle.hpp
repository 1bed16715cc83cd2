// The life of a track, decided from plain evidence:
//
//   tentative --confirmed--> confirmed --no fit--> lost --fit or restart--> confirmed
//       |                        |                  |
//       +-- stale, absent, sunk -+------------------+--> removed
//
// The pipeline gathers the evidence (this frame's refinement, ray counts, the static map, the
// detections, the scene graph) into plain structs and applies what the policies decide. Each rule
// is a named policy below; next() combines them into the one transition of a frame. None of them
// needs a ray-casting scene, so each is tested on hand-written evidence.
#pragma once

#include <limits>

#include "scene_graph_tracker/registration/object_refiner.hpp"

namespace sgt {

enum class TrackState { kTentative, kConfirmed, kLost, kRemoved };
const char* toString(TrackState s);

// The life-cycle options. PipelineOptions holds them under the same names, with their defaults
// and units; lifecycleOptions(PipelineOptions) in pipeline/frame_pipeline.hpp makes one of these.
struct LifecycleOptions {
  double association_distance;
  double reacquire_distance;
  int confirm_hits;
  int confirm_detections;
  double confirm_inlier_ratio;
  double confirm_presence_score;
  int min_weak_fit_inliers;
  double fit_support_weight;
  double min_fit_support;
  double remove_after_s;
  double remove_tentative_after_s;
  double tentative_timeout_s;
  double tentative_unseen_timeout_s;
  double lost_track_max_jump_m;
  double lost_track_resume_inlier_ratio;
  double research_below_fit_support;
  double orientation_search_interval_s;
  double dispute_angle_rad;  // a hypothesis turned farther than this from the track disputes it
  int disputes_to_contest;   // consecutive disputing hypotheses that contest the orientation
  int position_disputes_to_contest;  // the same for hypotheses placed beyond the track's gate
  int min_points;                    // the refiner's alignment.min_points: a fit needs this many
  double min_inlier_ratio;           // the refiner's: below it a fit explains nothing there
  double fit_turn_gate;  // chi-square bound (3 dof) on a fit's turn from the prediction; 0: off
};

// What a track knows of its own history.
struct TrackLife {
  TrackState state = TrackState::kTentative;
  int hits = 0;                 // good fits that counted towards confirmation
  int detections = 0;           // hypotheses associated with the track
  double fit_support = -1.0;    // running mean of its good fits' inlier ratios (< 0: none yet)
  double fit_closeness = -1.0;  // the same of their close ratios (ObjectQuality::close_ratio)
  double absent_since = -1.0;   // < 0: no evidence of absence
  double sunk_since = -1.0;     // < 0: not inside the static map
  double last_hypothesis = 0.0;
  double unseen_s = 0.0;     // time out of view (a fit no ray reaches) since the last hypothesis
  double last_stamp = -1.0;  // of the last frame applied (< 0: none yet)
  double last_orientation_search = -1e9;
  int orientation_disputes = 0;  // consecutive associated hypotheses turned away from the track
  int position_disputes = 0;     // consecutive associated hypotheses placed away from it
};

// What the rays of a frame say of a coasting track where it stands: there; missing (the rays that
// should reach it find nothing); hidden (too few rays reach it, or other tracks hide it: no
// evidence either way, so its absence clock pauses and absence counts over the time it is seen).
enum class Sighting { kThere, kMissing, kHidden };

// What one frame says about a track.
struct TrackEvidence {
  double stamp = 0.0;
  bool child = false;                    // in or on another track (its scene-graph parent moves it)
  ObjectQuality fit;                     // this frame's refinement
  double fit_jump_m = 0.0;               // how far the refinement moved it
  Sighting sighting = Sighting::kThere;  // a coasting track's
  // A track whose fit the turn gate refused, in view where it coasts (enough rays reach it): the
  // share of those rays its model there explains. < 0: none such.
  double coast_agreement = -1.0;
  // A tentative track's good fit: how much better the rays near it are explained with its model
  // than without (presenceScore); NaN where not weighed.
  double presence = std::numeric_limits<double>::quiet_NaN();
  bool sunk = false;               // its model lies partly inside the static map
  bool queued_for_search = false;  // an orientation search is already pending for it
};

// What this frame's refinement does to the track's pose.
enum class FitUse {
  kPlace,   // a weak fit places a tentative track (filter restarted there)
  kUpdate,  // a good fit updates the filter
  kCoast,   // no usable fit: the track coasts on its prediction (or with its parent)
};

struct Transition {
  TrackLife life;  // after this frame
  FitUse fit_use = FitUse::kCoast;
  bool search_orientation = false;  // queue an orientation search for it
  bool remove = false;
};

// A tentative track's fit from fewer points than a full fit needs still places it when it has
// min_weak_fit_inliers that explain confirm_inlier_ratio of its rays (a far, small object): the
// next frame refines from there, and no detection resets it. It counts neither as a hit nor
// towards fit support.
struct WeakFitPlacement {
  static bool places(TrackState state, bool child, const ObjectQuality& fit,
                     const LifecycleOptions& o);
};

// A lost track stays where it was lost unless a detection restarts it or it is seen whole again:
// a fit farther than lost_track_max_jump_m fitted something else, and one explaining less than
// lost_track_resume_inlier_ratio of its rays is a glimpse past an occluder.
struct LostTrackResume {
  static bool rejects(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o);
};

// An established track (confirmed or lost; not a child, which its parent moves) does not take a
// good fit whose rotation lies beyond fit_turn_gate of its predicted one (squared Mahalanobis
// distance `turn_distance2`, prediction and fit noise): the motion model says the object cannot
// have turned so far since the last frame, so the refiner has fitted a wrong turn to a few rays.
// Unless the turned fit explains a larger share of its rays closely than the track's fits have
// (close ratio against fit closeness): then the track was the wrong one (confirmed in a wrong
// turn) and the fit corrects it.
struct TurnGate {
  static bool rejects(const TrackLife& life, bool child, const ObjectQuality& fit,
                      double turn_distance2, const LifecycleOptions& o);
};

// The running share of the rays reaching a track's model that its measurements agree with: at
// its good fits, and where the turn gate keeps it (TrackEvidence::coast_agreement).
struct FitSupport {
  static double next(double support, double inlier_ratio, const LifecycleOptions& o);
  // A track (not a child, whose fits its parent cuts) whose fits the measurements contradict:
  // evidence of absence, and it explains no points in pre-segmentation.
  static bool unsupported(bool child, double support, const LifecycleOptions& o);
};

// A tentative track becomes a confirmed one after confirm_hits good fits that explain
// confirm_inlier_ratio of their rays, confirm_detections detections and min_fit_support.
struct Confirmation {
  static bool countsAsHit(TrackState state, double inlier_ratio, double presence,
                          const LifecycleOptions& o);
  static bool confirmed(const TrackLife& life, const LifecycleOptions& o);
};

// A confirmed track whose fits explain less than research_below_fit_support of its rays closely
// (fit closeness; in far, noisy depth a wrong turn still explains most rays within the noise)
// may be turned: searched again, no sooner than orientation_search_interval_s after the last
// search.
struct OrientationReSearch {
  static bool due(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o);
};

// Detections that keep seeing a track turned otherwise (beyond dispute_angle_rad, up to its
// symmetries) contest its orientation: after disputes_to_contest of them in a row, the latest
// detection's pose and the track's are refined briefly on the measurements and the better
// explained one goes on (the track's wins ties). Refinement is a local search: once a carried or
// half-hidden object has slipped into a wrong turn that explains its points about as well, only
// new evidence can get it out, and the detector sees the object's appearance, not its depth.
struct OrientationDispute {
  static int next(int disputes, double angle_rad, const LifecycleOptions& o);
  static bool contested(int disputes, const LifecycleOptions& o);
};

// Detections that keep seeing a track elsewhere contest its position: a hypothesis whose position
// lies beyond the 99.9 % bound of the track's predicted position (squared Mahalanobis distance
// `shift_distance2`, the filter's and the detection's noise) disputes it; after
// position_disputes_to_contest of them in a row the track's pose and the same pose moved to the
// latest detection's position are refined briefly on the measurements and the better explained
// one goes on (the track's wins ties; a moved track then searches its orientation). A track started
// from a poor detection can settle on the edge of its object or of a neighbour with fits good
// enough to go on: the refinement is local, and the detections that see the object elsewhere are
// the evidence that can move it.
struct PositionDispute {
  static constexpr double kGate = 16.27;  // 99.9 % of a chi-square with 3 degrees of freedom
  static int next(int disputes, double shift_distance2, const LifecycleOptions& o);
  static bool contested(int disputes, const LifecycleOptions& o);
};

// The model lies partly inside the static map: nowhere a real object can be.
struct SunkInMap {
  static double since(double sunk_since, bool child, bool sunk, double stamp);
};

// A track goes after remove_after_s (tentative: remove_tentative_after_s) of evidence of absence
// or of lying in the map. A tentative one also goes when it has been in view for
// tentative_timeout_s since its last detection (a false detection out of the sensors' reach never
// collects evidence of absence), and, in view or not, tentative_unseen_timeout_s after it.
struct Removal {
  static bool removes(const TrackLife& life, double stamp, const LifecycleOptions& o);
};

// Association of detections with tracks.
struct DetectionAssociation {
  // A track refined well this frame, or a child, is matched within association_distance; one
  // whose fit failed where rays reached it, seen missing, or tentative may have moved unseen
  // (reacquire_distance). One that no ray reached and that was not seen missing (out of view,
  // wholly hidden) is where it was last seen: a detection of its class farther away than
  // association_distance is another object, not this one moved.
  static bool mayHaveMoved(RefineStatus last_fit, const TrackLife& life);
  static double gate(RefineStatus last_fit, bool child, const TrackLife& life,
                     const LifecycleOptions& o);
  // A detection restarts a track whose fit failed (unless a weak fit placed it).
  static bool restarts(RefineStatus last_fit, bool placed_by_weak_fit);
};

// When a detection restarts a lost track, the track's own pose and the detection's are refined
// briefly and scored: the detection wins only when it scores better and its fit explains
// confirm_inlier_ratio of its rays. A track lying in the map does not compete.
struct RestartContest {
  static bool competes(bool track_sunk_in_map) { return !track_sunk_in_map; }
  static bool detectionWins(std::size_t winner, double winner_inlier_ratio,
                            const LifecycleOptions& o);
};

// Which tracks explain measurements in pre-segmentation: neither tentative ones (a false detection
// would hide an unknown thing) nor unsupported ones (on their way out).
struct PresegmentationRole {
  static bool explainsPoints(TrackState state, bool unsupported) {
    return state != TrackState::kTentative && !unsupported;
  }
};

FitUse useOfFit(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o);
// The one transition of a frame. Evidence of absence for a coasting track is its sighting.
Transition next(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o);

}  // namespace sgt
