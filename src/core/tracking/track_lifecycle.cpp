#include "scene_graph_tracker/tracking/track_lifecycle.hpp"

namespace sgt {
namespace {

// absent_since after a frame that does (absent) or does not show the track missing.
double absentSince(double since, bool absent, double stamp) {
  if (!absent) return -1.0;
  return since < 0.0 ? stamp : since;
}

// A good fit: fit support, hits, confirmation, a search for its orientation.
void takeGoodFit(Transition& t, const TrackLife& before, const TrackEvidence& e,
                 const LifecycleOptions& o) {
  TrackLife& life = t.life;
  life.fit_support = FitSupport::next(life.fit_support, e.fit.inlier_ratio, o);
  life.fit_closeness = FitSupport::next(life.fit_closeness, e.fit.close_ratio, o);
  const bool contradicted = FitSupport::unsupported(e.child, life.fit_support, o);
  life.absent_since = absentSince(life.absent_since,
                                  before.state != TrackState::kTentative && contradicted, e.stamp);
  if (Confirmation::countsAsHit(before.state, e.fit.inlier_ratio, e.presence, o)) ++life.hits;
  const bool confirmed = Confirmation::confirmed(life, o);
  // A real object now: is its rotation the right one?
  t.search_orientation = confirmed && before.state == TrackState::kTentative;
  if (OrientationReSearch::due(life, e, o)) t.search_orientation = true;
  if (confirmed || before.state == TrackState::kLost) life.state = TrackState::kConfirmed;
}

// No usable fit: evidence of absence, and a confirmed track is lost.
void coast(Transition& t, const TrackLife& before, const TrackEvidence& e,
           const LifecycleOptions& o) {
  TrackLife& life = t.life;
  // A child as well: walls that hide it make its frames hidden, not missing.
  bool absent = e.sighting == Sighting::kMissing;
  // The turn gate refused the fit but keeps the track in view: the measurements at the pose it
  // keeps support it as a taken fit's would (a track the gate keeps where an unknown thing stands
  // is contradicted as one whose fits are taken).
  if (e.coast_agreement >= 0.0) {
    life.fit_support = FitSupport::next(life.fit_support, e.coast_agreement, o);
    absent |= FitSupport::unsupported(e.child, life.fit_support, o);
  }
  if (!absent && e.sighting == Sighting::kHidden && life.absent_since >= 0.0 &&
      before.last_stamp >= 0.0)
    life.absent_since += e.stamp - before.last_stamp;  // paused while nothing can tell
  else
    life.absent_since = absentSince(life.absent_since, absent, e.stamp);
  if (before.state == TrackState::kConfirmed) life.state = TrackState::kLost;
}

}  // namespace

const char* toString(TrackState s) {
  switch (s) {
    case TrackState::kTentative:
      return "tentative";
    case TrackState::kConfirmed:
      return "confirmed";
    case TrackState::kLost:
      return "lost";
    case TrackState::kRemoved:
      return "removed";
  }
  return "?";
}

bool WeakFitPlacement::places(TrackState state, bool child, const ObjectQuality& fit,
                              const LifecycleOptions& o) {
  return !child && state == TrackState::kTentative && fit.status == RefineStatus::kTooFewPoints &&
         fit.inliers >= o.min_weak_fit_inliers && fit.inlier_ratio >= o.confirm_inlier_ratio;
}

bool LostTrackResume::rejects(const TrackLife& life, const TrackEvidence& e,
                              const LifecycleOptions& o) {
  const bool resumes_unaided = life.state == TrackState::kLost && life.last_hypothesis < e.stamp;
  return e.fit.status == RefineStatus::kOk && resumes_unaided &&
         (e.fit_jump_m > o.lost_track_max_jump_m ||
          e.fit.inlier_ratio < o.lost_track_resume_inlier_ratio);
}

bool TurnGate::rejects(const TrackLife& life, bool child, const ObjectQuality& fit,
                       double turn_distance2, const LifecycleOptions& o) {
  return o.fit_turn_gate > 0.0 && life.state != TrackState::kTentative && !child &&
         fit.status == RefineStatus::kOk && turn_distance2 > o.fit_turn_gate &&
         fit.close_ratio <= life.fit_closeness;
}

double FitSupport::next(double support, double inlier_ratio, const LifecycleOptions& o) {
  return support < 0.0 ? inlier_ratio : support + o.fit_support_weight * (inlier_ratio - support);
}

bool FitSupport::unsupported(bool child, double support, const LifecycleOptions& o) {
  return !child && support >= 0.0 && support < o.min_fit_support;
}

bool Confirmation::countsAsHit(TrackState state, double inlier_ratio, double presence,
                               const LifecycleOptions& o) {
  // A detection on something else (a walking person) lets a model fit a patch of it, but then
  // explains only part of its rays. A model whose rays the scene explains as well without it (a
  // second model of a tracked object, a flat one laid on the bench within the noise) shows
  // nothing new.
  const bool shows_something = !(presence < o.confirm_presence_score);
  return state != TrackState::kTentative ||
         (inlier_ratio >= o.confirm_inlier_ratio && shows_something);
}

bool Confirmation::confirmed(const TrackLife& life, const LifecycleOptions& o) {
  return life.hits >= o.confirm_hits && life.detections >= o.confirm_detections &&
         life.fit_support >= o.min_fit_support;
}

bool OrientationReSearch::due(const TrackLife& life, const TrackEvidence& e,
                              const LifecycleOptions& o) {
  return life.state == TrackState::kConfirmed && !e.child &&
         life.fit_closeness < o.research_below_fit_support &&
         e.stamp - life.last_orientation_search >= o.orientation_search_interval_s &&
         !e.queued_for_search;
}

int OrientationDispute::next(int disputes, double angle_rad, const LifecycleOptions& o) {
  return o.dispute_angle_rad > 0.0 && angle_rad > o.dispute_angle_rad ? disputes + 1 : 0;
}

bool OrientationDispute::contested(int disputes, const LifecycleOptions& o) {
  return o.disputes_to_contest > 0 && disputes >= o.disputes_to_contest;
}

int PositionDispute::next(int disputes, double shift_distance2, const LifecycleOptions& o) {
  return o.position_disputes_to_contest > 0 && shift_distance2 > kGate ? disputes + 1 : 0;
}

bool PositionDispute::contested(int disputes, const LifecycleOptions& o) {
  return o.position_disputes_to_contest > 0 && disputes >= o.position_disputes_to_contest;
}

double SunkInMap::since(double sunk_since, bool child, bool sunk, double stamp) {
  return absentSince(sunk_since, !child && sunk, stamp);
}

bool Removal::removes(const TrackLife& life, double stamp, const LifecycleOptions& o) {
  const bool tentative = life.state == TrackState::kTentative;
  const double limit = tentative ? o.remove_tentative_after_s : o.remove_after_s;
  // A tentative track that detections stopped confirming while it was in view goes.
  const double since = stamp - life.last_hypothesis;
  const bool stale = tentative && (since - life.unseen_s > o.tentative_timeout_s ||
                                   since > o.tentative_unseen_timeout_s);
  const bool sunk = life.sunk_since >= 0.0 && stamp - life.sunk_since >= limit;
  const bool absent = life.absent_since >= 0.0 && stamp - life.absent_since >= limit;
  return stale || sunk || absent;
}

bool DetectionAssociation::mayHaveMoved(RefineStatus last_fit, const TrackLife& life) {
  // Rays reached it and found no fit, or passed where it was: it may have moved. No ray reaching
  // it (out of view, wholly hidden) says nothing: it is where it was last seen.
  return life.state == TrackState::kTentative || life.absent_since >= 0.0 ||
         last_fit != RefineStatus::kNotVisible;
}

double DetectionAssociation::gate(RefineStatus last_fit, bool child, const TrackLife& life,
                                  const LifecycleOptions& o) {
  const bool refined = last_fit == RefineStatus::kOk;
  return refined || child || !mayHaveMoved(last_fit, life) ? o.association_distance
                                                           : o.reacquire_distance;
}

bool DetectionAssociation::restarts(RefineStatus last_fit, bool placed_by_weak_fit) {
  return last_fit != RefineStatus::kOk && !placed_by_weak_fit;
}

bool RestartContest::detectionWins(std::size_t winner, double winner_inlier_ratio,
                                   const LifecycleOptions& o) {
  // A false detection beside a hidden object fits the edge of what hides it with a quarter of
  // its rays, and more inliers than the hidden track has.
  return winner == 1 && winner_inlier_ratio >= o.confirm_inlier_ratio;
}

FitUse useOfFit(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o) {
  if (WeakFitPlacement::places(life.state, e.child, e.fit, o)) return FitUse::kPlace;
  if (e.fit.status == RefineStatus::kOk && !LostTrackResume::rejects(life, e, o))
    return FitUse::kUpdate;
  return FitUse::kCoast;
}

Transition next(const TrackLife& life, const TrackEvidence& e, const LifecycleOptions& o) {
  Transition t;
  t.life = life;
  t.fit_use = useOfFit(life, e, o);
  switch (t.fit_use) {
    case FitUse::kPlace:
      t.life.absent_since = -1.0;
      break;
    case FitUse::kUpdate:
      takeGoodFit(t, life, e, o);
      break;
    case FitUse::kCoast:
      coast(t, life, e, o);
      break;
  }
  t.life.sunk_since = SunkInMap::since(t.life.sunk_since, e.child, e.sunk, e.stamp);
  if (life.last_stamp >= 0.0 && e.fit.status == RefineStatus::kNotVisible)
    t.life.unseen_s += e.stamp - life.last_stamp;
  t.life.last_stamp = e.stamp;
  t.remove = Removal::removes(t.life, e.stamp, o);
  return t;
}

}  // namespace sgt
