// The track life cycle's policies and its transition function on hand-written evidence: no scene,
// no sensor, only the numbers a frame would give.
#include <gtest/gtest.h>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"
#include "scene_graph_tracker/tracking/track_lifecycle.hpp"

namespace sgt {
namespace {

const LifecycleOptions kOptions = lifecycleOptions(PipelineOptions{});  // the package's defaults

ObjectQuality fit(RefineStatus status, int inliers, double inlier_ratio, int expected = 200) {
  ObjectQuality q;
  q.status = status, q.inliers = inliers, q.inlier_ratio = inlier_ratio, q.expected = expected;
  q.close_ratio = inlier_ratio;  // no noise band
  return q;
}

TrackEvidence goodFit(double stamp, double inlier_ratio = 0.9) {
  TrackEvidence e;
  e.stamp = stamp;
  e.fit = fit(RefineStatus::kOk, 300, inlier_ratio);
  return e;
}

TrackEvidence noFit(double stamp, RefineStatus status = RefineStatus::kNotVisible) {
  TrackEvidence e;
  e.stamp = stamp;
  e.fit = fit(status, 0, 0.0, 0);
  return e;
}

TrackLife confirmedLife(double stamp) {
  TrackLife life;
  life.state = TrackState::kConfirmed;
  life.hits = life.detections = 5;
  life.fit_support = life.fit_closeness = 0.95;
  life.last_hypothesis = stamp;
  return life;
}

TEST(WeakFitPlacement, PlacesATentativeTrackFromAFewAgreeingPoints) {
  const ObjectQuality weak = fit(RefineStatus::kTooFewPoints, 8, 0.7);
  EXPECT_TRUE(WeakFitPlacement::places(TrackState::kTentative, false, weak, kOptions));
  EXPECT_FALSE(
      WeakFitPlacement::places(TrackState::kConfirmed, false, weak, kOptions));  // tentative only
  EXPECT_FALSE(
      WeakFitPlacement::places(TrackState::kTentative, true, weak, kOptions));  // not a child
  EXPECT_FALSE(WeakFitPlacement::places(TrackState::kTentative, false,
                                        fit(RefineStatus::kTooFewPoints, 5, 0.7),
                                        kOptions));  // too few
  EXPECT_FALSE(WeakFitPlacement::places(TrackState::kTentative, false,
                                        fit(RefineStatus::kTooFewPoints, 8, 0.5),
                                        kOptions));  // explains too little
  EXPECT_FALSE(WeakFitPlacement::places(TrackState::kTentative, false,
                                        fit(RefineStatus::kOk, 8, 0.7), kOptions));
}

TEST(WeakFitPlacement, TheTransitionPlacesWithoutAHitAndClearsAbsence) {
  TrackLife life;
  life.absent_since = 1.0;
  TrackEvidence e;
  e.stamp = 1.1;
  e.fit = fit(RefineStatus::kTooFewPoints, 8, 0.7);
  const Transition t = next(life, e, kOptions);
  EXPECT_EQ(t.fit_use, FitUse::kPlace);
  EXPECT_EQ(t.life.hits, 0);
  EXPECT_LT(t.life.fit_support, 0.0);
  EXPECT_LT(t.life.absent_since, 0.0);
}

TEST(LostTrackResume, RejectsAFarOrPartialFitUntilADetectionRestartsIt) {
  TrackLife lost = confirmedLife(1.0);
  lost.state = TrackState::kLost;
  TrackEvidence e = goodFit(2.0);
  e.fit_jump_m = 0.02;
  EXPECT_FALSE(LostTrackResume::rejects(lost, e, kOptions));
  e.fit_jump_m = 0.1;  // fitted something else
  EXPECT_TRUE(LostTrackResume::rejects(lost, e, kOptions));
  EXPECT_EQ(useOfFit(lost, e, kOptions), FitUse::kCoast);
  e.fit_jump_m = 0.0, e.fit.inlier_ratio = 0.6;  // a glimpse past an occluder
  EXPECT_TRUE(LostTrackResume::rejects(lost, e, kOptions));
  lost.last_hypothesis = 2.0;  // restarted by this frame's detection: any good fit goes
  EXPECT_FALSE(LostTrackResume::rejects(lost, e, kOptions));
  EXPECT_FALSE(LostTrackResume::rejects(confirmedLife(1.0), e, kOptions));  // only lost tracks
}

TEST(TurnGate, AnEstablishedTrackCoastsThroughAFitTurnedBeyondTheGate) {
  LifecycleOptions on = kOptions;
  on.fit_turn_gate = 16.27;
  // A track whose fits have explained 95 % of their rays; the turned fit explains 60 %.
  const auto rejects = [&](TrackState s, bool child, RefineStatus status, double d2,
                           double ratio = 0.6) {
    TrackLife life = confirmedLife(0.9);
    life.state = s;
    return TurnGate::rejects(life, child, fit(status, 120, ratio), d2, on);
  };
  EXPECT_TRUE(rejects(TrackState::kConfirmed, false, RefineStatus::kOk, 17.0));
  EXPECT_TRUE(rejects(TrackState::kLost, false, RefineStatus::kOk, 17.0));
  EXPECT_FALSE(rejects(TrackState::kConfirmed, false, RefineStatus::kOk, 16.0));  // within
  EXPECT_FALSE(rejects(TrackState::kTentative, false, RefineStatus::kOk, 1e6));   // not established
  EXPECT_FALSE(rejects(TrackState::kConfirmed, true, RefineStatus::kOk, 1e6));    // a child
  EXPECT_FALSE(rejects(TrackState::kConfirmed, false, RefineStatus::kTooFewPoints, 1e6));
  // A turned fit that explains more of its rays than the track's fits did corrects the track.
  EXPECT_FALSE(rejects(TrackState::kConfirmed, false, RefineStatus::kOk, 1e6, 0.99));
  // ... closely: within the noise band alone (a far object in noisy depth) it does not.
  ObjectQuality banded = fit(RefineStatus::kOk, 120, 0.99);
  banded.close_ratio = 0.6;
  EXPECT_TRUE(TurnGate::rejects(confirmedLife(0.9), false, banded, 1e6, on));
  LifecycleOptions off = on;
  off.fit_turn_gate = 0.0;
  EXPECT_FALSE(
      TurnGate::rejects(confirmedLife(0.9), false, fit(RefineStatus::kOk, 120, 0.6), 1e6, off));
  // A rejected fit is no good fit: a confirmed track coasts and is lost.
  TrackEvidence e = goodFit(1.0);
  e.fit.status = RefineStatus::kImplausibleTurn;
  const Transition t = next(confirmedLife(0.9), e, on);
  EXPECT_EQ(t.fit_use, FitUse::kCoast);
  EXPECT_EQ(t.life.state, TrackState::kLost);
}

TEST(FitSupport, IsARunningMeanThatStartsAtTheFirstFit) {
  EXPECT_DOUBLE_EQ(FitSupport::next(-1.0, 0.8, kOptions), 0.8);
  EXPECT_DOUBLE_EQ(FitSupport::next(0.8, 0.4, kOptions), 0.8 + 0.25 * (0.4 - 0.8));
  EXPECT_FALSE(FitSupport::unsupported(false, -1.0, kOptions));  // no fit yet
  EXPECT_TRUE(FitSupport::unsupported(false, 0.5, kOptions));
  EXPECT_FALSE(
      FitSupport::unsupported(true, 0.5, kOptions));  // a child's fits are cut by its parent
  EXPECT_FALSE(FitSupport::unsupported(false, 0.7, kOptions));
}

TEST(FitSupport, AConfirmedTrackWhoseFitsExplainLittleCollectsAbsenceAndGoes) {
  TrackLife life = confirmedLife(0.0);
  life.fit_support = 0.5;
  Transition t = next(life, goodFit(1.0, 0.4), kOptions);
  EXPECT_EQ(t.life.state, TrackState::kConfirmed);
  EXPECT_DOUBLE_EQ(t.life.absent_since, 1.0);
  EXPECT_FALSE(t.remove);
  t = next(t.life, goodFit(2.0, 0.4), kOptions);
  EXPECT_TRUE(t.remove);  // remove_after_s of it
  // A tentative track's poor fits are no evidence of absence (it has not been confirmed).
  TrackLife tentative;
  tentative.last_hypothesis = 1.0;
  EXPECT_LT(next(tentative, goodFit(1.0, 0.4), kOptions).life.absent_since, 0.0);
}

// Where the turn gate keeps a track in view, the measurements at its model support it as a taken
// fit's would: too little agreement contradicts it and removes it; enough keeps it; out of view
// they leave its support alone.
TEST(FitSupport, WhereTheTurnGateKeepsATrackTheMeasurementsCount) {
  const auto coasting = [](double stamp, double agreement) {
    TrackEvidence e = goodFit(stamp, 0.9);
    e.fit.status = RefineStatus::kImplausibleTurn;
    e.coast_agreement = agreement;
    return e;
  };
  Transition t{};
  t.life = confirmedLife(0.0);
  double stamp = 0.0;
  while (!FitSupport::unsupported(false, t.life.fit_support, kOptions) && stamp < 1.0) {
    stamp += 0.1;
    t = next(t.life, coasting(stamp, 0.4), kOptions);
    EXPECT_EQ(t.fit_use, FitUse::kCoast);
  }
  EXPECT_NEAR(stamp, 0.3, 1e-9) << "0.95 falls below 0.65 in three frames agreeing 40 %";
  EXPECT_DOUBLE_EQ(t.life.absent_since, stamp);
  t = next(t.life, coasting(stamp + kOptions.remove_after_s, 0.4), kOptions);
  EXPECT_TRUE(t.remove);
  for (double agreement : {0.9, -1.0}) {
    t.life = confirmedLife(0.0);
    for (int f = 1; f <= 40; ++f) t = next(t.life, coasting(0.1 * f, agreement), kOptions);
    EXPECT_EQ(t.life.state, TrackState::kLost);
    EXPECT_LT(t.life.absent_since, 0.0);
    EXPECT_FALSE(t.remove);
  }
  EXPECT_DOUBLE_EQ(t.life.fit_support, 0.95) << "out of view: unchanged";
}

TEST(Confirmation, NeedsHitsDetectionsAndSupport) {
  TrackLife life;
  life.detections = 3;
  life.last_hypothesis = 0.0;
  for (int frame = 0; frame < 2; ++frame) {
    const Transition t = next(life, goodFit(0.1 * frame), kOptions);
    EXPECT_EQ(t.life.state, TrackState::kTentative);
    EXPECT_FALSE(t.search_orientation);
    life = t.life;
  }
  const Transition t = next(life, goodFit(0.2), kOptions);
  EXPECT_EQ(t.life.state, TrackState::kConfirmed);
  EXPECT_TRUE(t.search_orientation);  // a real object now: is its rotation the right one?
  TrackLife few = life;
  few.detections = 2;
  EXPECT_EQ(next(few, goodFit(0.2), kOptions).life.state, TrackState::kTentative);
}

TEST(Confirmation, FitsExplainingTooFewRaysAreNoHits) {
  EXPECT_FALSE(Confirmation::countsAsHit(TrackState::kTentative, 0.5, 10.0, kOptions));
  EXPECT_TRUE(Confirmation::countsAsHit(TrackState::kTentative, 0.6, 10.0, kOptions));
  EXPECT_TRUE(Confirmation::countsAsHit(TrackState::kConfirmed, 0.5, 10.0, kOptions));
  TrackLife life;
  life.detections = 10;
  for (int frame = 0; frame < 10; ++frame)
    life = next(life, goodFit(0.1 * frame, 0.5), kOptions).life;
  EXPECT_EQ(life.hits, 0);
  EXPECT_EQ(life.state, TrackState::kTentative);
}

TEST(Absence, ATentativeTracksFailedFitIsNoEvidenceOfAbsenceButRaysSeenThroughItAre) {
  // Far in noisy depth a present object's fit explains few of its rays (a false hypothesis).
  TrackEvidence e = noFit(0.1, RefineStatus::kFalseHypothesis);
  e.fit.expected = 100, e.fit.inliers = 10, e.fit.inlier_ratio = 0.1;
  EXPECT_LT(next(TrackLife{}, e, kOptions).life.absent_since, 0.0);
  e.sighting = Sighting::kMissing;  // most of its rays pass through where it should be
  EXPECT_DOUBLE_EQ(next(TrackLife{}, e, kOptions).life.absent_since, 0.1);
  e.sighting = Sighting::kHidden;  // in a container: its walls hide it
  EXPECT_LT(next(TrackLife{}, e, kOptions).life.absent_since, 0.0);
}

TEST(Removal, ATentativeTrackGoesQuicklyOnAbsenceAndWhenDetectionsStop) {
  TrackLife life;
  life.last_hypothesis = 0.0;
  TrackEvidence e = noFit(0.1, RefineStatus::kFalseHypothesis);
  e.sighting = Sighting::kMissing;
  Transition t = next(life, e, kOptions);
  EXPECT_DOUBLE_EQ(t.life.absent_since, 0.1);
  e.stamp = 0.3;
  EXPECT_FALSE(next(t.life, e, kOptions).remove);
  e.stamp = 0.5;
  EXPECT_TRUE(next(t.life, e, kOptions).remove);  // remove_tentative_after_s
  // In view without detections or evidence either way, it goes tentative_timeout_s after its last
  // detection.
  EXPECT_FALSE(next(life, noFit(1.0, RefineStatus::kFalseHypothesis), kOptions).remove);
  EXPECT_TRUE(next(life, noFit(1.01, RefineStatus::kFalseHypothesis), kOptions).remove);
}

TEST(Removal, ATentativeTracksTimeOutOfViewDoesNotCountTowardsItsTimeout) {
  TrackLife life;
  life.last_hypothesis = 0.0;
  Transition t = next(life, noFit(0.0, RefineStatus::kFalseHypothesis), kOptions);
  double stamp = 0.0;
  for (int frame = 0; frame < 90; ++frame) {  // 3 s out of view (no ray reaches it)
    stamp += 1.0 / 30.0;
    t = next(t.life, noFit(stamp), kOptions);
    ASSERT_FALSE(t.remove) << stamp;
  }
  EXPECT_NEAR(t.life.unseen_s, 3.0, 1e-9);
  // Back in view: it still has tentative_timeout_s for a detection to come.
  t = next(t.life, noFit(stamp + 0.9, RefineStatus::kFalseHypothesis), kOptions);
  EXPECT_FALSE(t.remove);
  EXPECT_TRUE(next(t.life, noFit(stamp + 1.1, RefineStatus::kFalseHypothesis), kOptions).remove);
  // Out of view for good, it goes tentative_unseen_timeout_s after its last detection.
  EXPECT_FALSE(next(t.life, noFit(9.9), kOptions).remove);
  EXPECT_TRUE(next(t.life, noFit(10.1), kOptions).remove);
}

TEST(Removal, AConfirmedTrackIsLostWhenUnseenAndGoesOnlyOnEvidenceOfAbsence) {
  TrackLife life = confirmedLife(0.0);
  Transition t = next(life, noFit(0.1), kOptions);
  EXPECT_EQ(t.fit_use, FitUse::kCoast);
  EXPECT_EQ(t.life.state, TrackState::kLost);
  for (double stamp = 0.2; stamp < 30.0; stamp += 1.0) {  // hidden for long: kept
    t = next(t.life, noFit(stamp), kOptions);
    EXPECT_FALSE(t.remove);
  }
  TrackEvidence seen_missing = noFit(30.0, RefineStatus::kFalseHypothesis);
  seen_missing.sighting = Sighting::kMissing;
  t = next(t.life, seen_missing, kOptions);
  EXPECT_FALSE(t.remove);
  seen_missing.stamp = 31.0;
  EXPECT_TRUE(next(t.life, seen_missing, kOptions).remove);
}

// A track left behind in the air where a carried object was: seen missing for 0.6 s, out of view
// for 1.5 s while the robot turns, seen missing again. The hidden frames neither clear nor count.
TEST(Removal, EvidenceOfAbsenceAddsUpOverTheFramesThatSeeTheTrack) {
  Transition t{};
  t.life = confirmedLife(0.0);
  TrackEvidence missing = noFit(0.0, RefineStatus::kFalseHypothesis);
  missing.sighting = Sighting::kMissing;
  TrackEvidence hidden = noFit(0.0);
  hidden.sighting = Sighting::kHidden;
  double stamp = 0.0;
  const auto frames = [&](TrackEvidence e, double seconds) {
    for (const double end = stamp + seconds - 1e-9; stamp < end;) {
      e.stamp = stamp += 0.1;
      t = next(t.life, e, kOptions);
      if (t.remove) return;
    }
  };
  frames(missing, 0.6);
  frames(hidden, 1.5);
  EXPECT_FALSE(t.remove) << "0.5 s of absence seen, the rest hidden";
  frames(missing, 0.4);
  EXPECT_FALSE(t.remove) << "0.9 s: frames 0.1-0.6 s and 2.1-2.5 s";
  frames(missing, 0.3);
  EXPECT_TRUE(t.remove) << "1 s seen missing, at " << stamp;
  EXPECT_NEAR(stamp, 2.6, 1e-9);
  // A frame that sees it there clears the clock; one that cannot tell does not.
  t.life = confirmedLife(0.0), stamp = 0.0;
  frames(missing, 0.6);
  frames(noFit(0.0), 0.1);
  EXPECT_LT(t.life.absent_since, 0.0);
}

TEST(Removal, ALostTrackSeenWholeAgainIsConfirmedAndClearsAbsence) {
  TrackLife life = confirmedLife(0.0);
  life.state = TrackState::kLost;
  life.absent_since = 0.5;
  const Transition t = next(life, goodFit(1.2), kOptions);
  EXPECT_EQ(t.fit_use, FitUse::kUpdate);
  EXPECT_EQ(t.life.state, TrackState::kConfirmed);
  EXPECT_LT(t.life.absent_since, 0.0);
  EXPECT_FALSE(t.remove);
}

TEST(Removal, AChildHiddenByItsContainerStaysAndOneSeenMissingGoes) {
  TrackLife life = confirmedLife(0.0);
  TrackEvidence e = noFit(0.1, RefineStatus::kFalseHypothesis);
  e.child = true;
  e.sighting = Sighting::kHidden;  // its container's walls: too few rays reach it
  for (double stamp = 0.1; stamp < 10.0; stamp += 0.5) {
    e.stamp = stamp;
    const Transition t = next(life, e, kOptions);
    EXPECT_LT(t.life.absent_since, 0.0);
    EXPECT_FALSE(t.remove);
    life = t.life;
  }
  // The rays reach where it is held and pass it: taken out unseen, or never there.
  e.sighting = Sighting::kMissing;
  e.stamp = 10.0;
  Transition t = next(life, e, kOptions);
  EXPECT_DOUBLE_EQ(t.life.absent_since, 10.0);
  EXPECT_FALSE(t.remove);
  e.stamp = 10.0 + kOptions.remove_after_s;
  EXPECT_TRUE(next(t.life, e, kOptions).remove);
  EXPECT_DOUBLE_EQ(DetectionAssociation::gate(RefineStatus::kNotVisible, true, t.life, kOptions),
                   kOptions.association_distance);
}

TEST(SunkInMap, ATrackInsideTheMapGoesSeenOrNotButNotAChild) {
  TrackLife life = confirmedLife(0.0);
  TrackEvidence e = goodFit(0.0);
  e.sunk = true;
  Transition t = next(life, e, kOptions);
  EXPECT_DOUBLE_EQ(t.life.sunk_since, 0.0);
  e.stamp = 1.0;
  EXPECT_TRUE(next(t.life, e, kOptions).remove);
  e.child = true;  // a child is where its parent holds it
  EXPECT_LT(next(t.life, e, kOptions).life.sunk_since, 0.0);
  EXPECT_DOUBLE_EQ(SunkInMap::since(-1.0, false, true, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(SunkInMap::since(2.0, false, true, 3.0), 2.0);
  EXPECT_DOUBLE_EQ(SunkInMap::since(2.0, false, false, 3.0), -1.0);
}

TEST(OrientationReSearch, AConfirmedTrackExplainingTooLittleIsSearchedAgainAfterTheInterval) {
  TrackLife life = confirmedLife(0.0);
  life.fit_support = life.fit_closeness = 0.8;
  life.last_orientation_search = 0.0;
  EXPECT_FALSE(next(life, goodFit(1.0, 0.8), kOptions).search_orientation);  // too soon
  EXPECT_TRUE(next(life, goodFit(2.0, 0.8), kOptions).search_orientation);
  TrackEvidence queued = goodFit(2.0, 0.8);
  queued.queued_for_search = true;
  EXPECT_FALSE(next(life, queued, kOptions).search_orientation);
  TrackLife nearly = life;
  nearly.fit_support = nearly.fit_closeness = 0.89;
  EXPECT_FALSE(next(nearly, goodFit(2.0, 1.0), kOptions).search_orientation);  // support back up
  // Far in noisy depth a turned track explains nearly all rays within the noise band, but few
  // closely: its closeness decides.
  TrackLife banded = life;
  banded.fit_support = 0.99;
  TrackEvidence close_few = goodFit(2.0, 0.99);
  close_few.fit.close_ratio = 0.6;
  EXPECT_TRUE(next(banded, close_few, kOptions).search_orientation);
  TrackEvidence child = goodFit(2.0, 0.8);
  child.child = true;
  EXPECT_FALSE(next(life, child, kOptions).search_orientation);
  LifecycleOptions off = kOptions;
  off.research_below_fit_support = 0.0;
  EXPECT_FALSE(next(life, goodFit(2.0, 0.8), off).search_orientation);
}

TEST(OrientationDispute, DetectionsTurnedAwayInARowContestTheOrientationAndOneAgreeingEndsIt) {
  const double turned = kOptions.dispute_angle_rad + 0.01,
               close = kOptions.dispute_angle_rad - 0.01;
  int disputes = 0;
  for (int i = 1; i < kOptions.disputes_to_contest; ++i) {
    disputes = OrientationDispute::next(disputes, turned, kOptions);
    EXPECT_FALSE(OrientationDispute::contested(disputes, kOptions)) << i;
  }
  EXPECT_EQ(OrientationDispute::next(disputes, close, kOptions), 0);  // one agrees: start over
  disputes = OrientationDispute::next(disputes, turned, kOptions);
  EXPECT_TRUE(OrientationDispute::contested(disputes, kOptions));
  LifecycleOptions off = kOptions;
  off.dispute_angle_rad = 0.0;
  EXPECT_EQ(OrientationDispute::next(5, M_PI, off), 0);
  off = kOptions;
  off.disputes_to_contest = 0;
  EXPECT_FALSE(OrientationDispute::contested(100, off));
}

// The gate is the filter's predicted position noise plus the detection's: here 1 cm and 2 cm,
// so the 99.9 % bound lies at sqrt(16.27 * 5e-4) = 9.0 cm whatever the detection's turn.
TEST(PositionDispute, DetectionsPlacedBeyondTheTracksGateInARowContestItsPosition) {
  const PoseFilter filter(Eigen::Isometry3d::Identity(), diagonalCovariance(0.01, 0.05));
  const auto C = diagonalCovariance(0.02, 0.08);
  const auto at = [](double x, double turn) {
    Eigen::Isometry3d T(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()));
    T.translation() = Eigen::Vector3d(x, 0.0, 0.0);
    return T;
  };
  const double far = filter.shiftDistance2(at(0.10, 0.0), C),
               near = filter.shiftDistance2(at(0.08, 0.0), C);
  EXPECT_GT(far, PositionDispute::kGate);
  EXPECT_LT(near, PositionDispute::kGate);
  EXPECT_DOUBLE_EQ(filter.shiftDistance2(at(0.08, M_PI / 2), C), near);  // the turn does not count
  LifecycleOptions on = kOptions;
  on.position_disputes_to_contest = 3;  // off by default (a candidate)
  int disputes = 0;
  for (int i = 1; i < on.position_disputes_to_contest; ++i) {
    disputes = PositionDispute::next(disputes, far, on);
    EXPECT_FALSE(PositionDispute::contested(disputes, on)) << i;
  }
  EXPECT_EQ(PositionDispute::next(disputes, near, on), 0);  // one agrees: start over
  for (int i = 0; i < on.position_disputes_to_contest; ++i)
    disputes = PositionDispute::next(disputes, far, on);
  EXPECT_TRUE(PositionDispute::contested(disputes, on));
  LifecycleOptions off = on;
  off.position_disputes_to_contest = 0;
  EXPECT_EQ(PositionDispute::next(5, far, off), 0);
  EXPECT_FALSE(PositionDispute::contested(100, off));
}

TEST(DetectionAssociation, GatesAndRestarts) {
  const TrackLife lost = [] {
    TrackLife l = confirmedLife(0.0);
    l.state = TrackState::kLost;
    return l;
  }();
  EXPECT_DOUBLE_EQ(DetectionAssociation::gate(RefineStatus::kOk, false, lost, kOptions),
                   kOptions.association_distance);
  // Rays reached it and found no fit: it may have moved.
  EXPECT_DOUBLE_EQ(DetectionAssociation::gate(RefineStatus::kTooFewPoints, false, lost, kOptions),
                   kOptions.reacquire_distance);
  // No ray reached it (out of view, wholly hidden): it is where it was, unless seen missing there
  // before or only a detection placed it.
  EXPECT_DOUBLE_EQ(DetectionAssociation::gate(RefineStatus::kNotVisible, false, lost, kOptions),
                   kOptions.association_distance);
  TrackLife missing = lost;
  missing.absent_since = 1.0;
  EXPECT_DOUBLE_EQ(DetectionAssociation::gate(RefineStatus::kNotVisible, false, missing, kOptions),
                   kOptions.reacquire_distance);
  TrackLife tentative;
  EXPECT_DOUBLE_EQ(
      DetectionAssociation::gate(RefineStatus::kNotVisible, false, tentative, kOptions),
      kOptions.reacquire_distance);
  EXPECT_FALSE(DetectionAssociation::restarts(RefineStatus::kOk, false));
  EXPECT_TRUE(DetectionAssociation::restarts(RefineStatus::kNotVisible, false));
  EXPECT_FALSE(
      DetectionAssociation::restarts(RefineStatus::kTooFewPoints, true));  // a weak fit placed it
}

TEST(RestartContest, TheDetectionWinsOnlyWithABetterFitThatExplainsItsRays) {
  EXPECT_FALSE(
      RestartContest::detectionWins(0, 0.9, kOptions));  // the track's own pose won (or a tie)
  EXPECT_TRUE(RestartContest::detectionWins(1, 0.9, kOptions));
  EXPECT_FALSE(RestartContest::detectionWins(1, 0.25, kOptions));  // the edge of an occluder
  EXPECT_TRUE(RestartContest::competes(false));
  EXPECT_FALSE(RestartContest::competes(true));
}

TEST(PresegmentationRole, OnlyConfirmedSupportedTracksExplainPoints) {
  EXPECT_FALSE(PresegmentationRole::explainsPoints(TrackState::kTentative, false));
  EXPECT_TRUE(PresegmentationRole::explainsPoints(TrackState::kConfirmed, false));
  EXPECT_TRUE(PresegmentationRole::explainsPoints(TrackState::kLost, false));
  EXPECT_FALSE(PresegmentationRole::explainsPoints(TrackState::kConfirmed, true));
}

TEST(TrackState, HasNames) {
  EXPECT_STREQ(toString(TrackState::kTentative), "tentative");
  EXPECT_STREQ(toString(TrackState::kConfirmed), "confirmed");
  EXPECT_STREQ(toString(TrackState::kLost), "lost");
  EXPECT_STREQ(toString(TrackState::kRemoved), "removed");
}

}  // namespace
}  // namespace sgt
