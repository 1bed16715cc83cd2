// FramePipeline: each frame's fits applied to the track filters, the evidence that needs the
// scene, and the life-cycle transitions (tracking/track_lifecycle.hpp) applied to the tracks.
#include <algorithm>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

namespace sgt {

LifecycleOptions lifecycleOptions(const PipelineOptions& p) {
  LifecycleOptions o{};
  o.association_distance = p.association_distance, o.reacquire_distance = p.reacquire_distance;
  o.confirm_hits = p.confirm_hits, o.confirm_detections = p.confirm_detections;
  o.confirm_inlier_ratio = p.confirm_inlier_ratio, o.min_weak_fit_inliers = p.min_weak_fit_inliers;
  o.confirm_presence_score = p.confirm_presence_score;
  o.fit_support_weight = p.fit_support_weight, o.min_fit_support = p.min_fit_support;
  o.remove_after_s = p.remove_after_s, o.remove_tentative_after_s = p.remove_tentative_after_s;
  o.tentative_timeout_s = p.tentative_timeout_s;
  o.tentative_unseen_timeout_s = p.tentative_unseen_timeout_s;
  o.lost_track_max_jump_m = p.lost_track_max_jump_m;
  o.lost_track_resume_inlier_ratio = p.lost_track_resume_inlier_ratio;
  o.research_below_fit_support = p.research_below_fit_support;
  o.orientation_search_interval_s = p.orientation_search_interval_s;
  o.dispute_angle_rad = p.orientation_dispute_deg * M_PI / 180.0;
  o.disputes_to_contest = p.orientation_disputes;
  o.position_disputes_to_contest = p.position_disputes;
  o.min_points = p.refiner.alignment.min_points, o.min_inlier_ratio = p.refiner.min_inlier_ratio;
  o.fit_turn_gate = p.fit_turn_gate;
  return o;
}

namespace {

// The continuous symmetry axes of an object at `T` (world frame).
std::vector<Eigen::Vector3d> symmetryAxes(const Symmetry& s, const Eigen::Isometry3d& T) {
  std::vector<Eigen::Vector3d> axes;
  for (const ContinuousSymmetry& c : s.continuous) axes.push_back(T.linear() * c.axis.normalized());
  return axes;
}

}  // namespace

bool FramePipeline::unsupported(const Track& t) const {
  return FitSupport::unsupported(isChild(t.out.node), t.life.fit_support, lifecycleOptions());
}

bool FramePipeline::placedByWeakFit(const Track& t) const {
  return WeakFitPlacement::places(t.life.state, isChild(t.out.node), t.out.quality,
                                  lifecycleOptions());
}

void FramePipeline::updateTracks(const RefineResult& r, const std::vector<RangeMeasurements>& sets,
                                 double stamp, std::vector<std::string>& dropped) {
  const LifecycleOptions lo = lifecycleOptions();
  const std::vector<std::size_t> order =
      parentsFirst();  // a coasting child follows its parent's new pose
  std::vector<TrackEvidence> evidence(tracks_.size());
  std::vector<FitUse> uses(tracks_.size());
  for (std::size_t k : order) {
    const TrackLife& before = tracks_[k].life;
    evidence[k] = applyFit(k, r.objects[k], sets, stamp, lo);
    uses[k] = useOfFit(before, evidence[k], lo);
  }
  gatherSceneEvidence(evidence, uses, order, sets);
  std::vector<bool> remove(tracks_.size(), false);
  for (std::size_t k : order) {
    Track& t = tracks_[k];
    evidence[k].queued_for_search = std::find(needs_orientation_.begin(), needs_orientation_.end(),
                                              t.out.id) != needs_orientation_.end();
    const Transition next_state = next(t.life, evidence[k], lo);
    t.life = next_state.life;
    if (next_state.search_orientation) needs_orientation_.push_back(t.out.id);
    remove[k] = next_state.remove;
  }
  noteUnlocated(remove, stamp);
  for (std::size_t k = tracks_.size(); k-- > 0;)
    if (remove[k]) dropped.push_back(tracks_[k].out.id), dropTrack(k);
}

void FramePipeline::noteUnlocated(const std::vector<bool>& remove, double stamp) {
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Track& t = tracks_[k];
    const bool established = t.life.state != TrackState::kTentative;
    if (!remove[k] && t.life.state == TrackState::kConfirmed) unlocated_.found(t.out.id);
    if (remove[k] && established && options_.unlocated_keep_s > 0.0)
      unlocated_.add(t.out.id, t.out.class_name, t.out.T_map_object.translation(), stamp);
    else if (remove[k])
      unlocated_.release(t.out.id);
  }
  unlocated_.expire(stamp, options_.unlocated_keep_s);
}

bool FramePipeline::turnedBeyondGate(const Track& t, const TrackEvidence& e,
                                     const Eigen::Isometry3d& T_fit,
                                     const LifecycleOptions& lo) const {
  if (lo.fit_turn_gate <= 0.0) return false;
  const double d2 = t.filter.turnDistance2(
      T_fit, diagonalCovariance(options_.refined_sigma_m, options_.refined_sigma_rad),
      &catalog_->get(t.out.class_name).symmetry);
  return TurnGate::rejects(t.life, e.child, e.fit, d2, lo);
}

TrackEvidence FramePipeline::applyFit(std::size_t k, const ObjectEstimate& fit,
                                      const std::vector<RangeMeasurements>& sets, double stamp,
                                      const LifecycleOptions& lo) {
  Track& t = tracks_[k];
  TrackedObject& o = t.out;
  o.quality = fit.quality;
  TrackEvidence e;
  e.stamp = stamp;
  e.child = isChild(o.node);
  e.fit = fit.quality;
  e.fit_jump_m = (fit.T_world_object.translation() - o.T_map_object.translation()).norm();
  const Symmetry* symmetry = &catalog_->get(o.class_name).symmetry;
  const auto C_follow =
      diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  if (turnedBeyondGate(t, e, fit.T_world_object, lo))
    e.fit.status = o.quality.status = RefineStatus::kImplausibleTurn;
  switch (useOfFit(t.life, e, lo)) {
    case FitUse::kPlace:  // the next frame refines from the weak fit
      t.filter = PoseFilter(fit.T_world_object, C_follow, options_.motion);
      o.T_map_object = fit.T_world_object;
      break;
    case FitUse::kUpdate: {
      // A fit from few points or from far away is a weaker measurement, and the track reports
      // the filtered pose rather than that fit. Not for a child: its filter does not follow its
      // parent's motion.
      const double weak = e.child ? 1.0 : fitWeakness(o, sets);
      const auto C0 = diagonalCovariance(options_.refined_sigma_m, options_.refined_sigma_rad);
      PoseFilter::Mat6 C = C0 * weak;
      bool loose = false;
      if (options_.fit_point_sigma_m > 0.0 && !e.child) {
        const auto C_rays = fitCovariance(fit.quality.information, options_.fit_point_sigma_m,
                                          symmetryAxes(*symmetry, fit.T_world_object));
        C += C_rays;
        loose = looserThan(C_rays, C0);
      }
      t.filter.update(fit.T_world_object, C, symmetry);
      o.T_map_object = weak > 1.0 || loose ? t.filter.pose() : fit.T_world_object;
      o.last_refined = stamp;
      break;
    }
    case FitUse::kCoast:  // on the prediction; a child where its parent holds it
      if (e.child) t.filter.update(graph_.worldTransform(o.node), C_follow, symmetry);
      o.T_map_object = e.child ? graph_.worldTransform(o.node) : t.filter.pose();
      break;
  }
  o.covariance = t.filter.poseCovariance();
  scene_.setInstancePose(o.node, o.T_map_object);
  graph_.setWorldTransform(o.node, o.T_map_object);
  return e;
}

void FramePipeline::gatherSceneEvidence(std::vector<TrackEvidence>& evidence,
                                        const std::vector<FitUse>& uses,
                                        const std::vector<std::size_t>& order,
                                        const std::vector<RangeMeasurements>& sets) {
  // Evidence of absence of a coasting track, at the pose it coasts at.
  std::vector<std::size_t> coasting;
  for (std::size_t k : order)
    if (uses[k] == FitUse::kCoast) coasting.push_back(k);
  if (!coasting.empty()) scene_.commit();
  for (std::size_t k : coasting) {
    TrackEvidence& e = evidence[k];
    const bool gated = e.fit.status == RefineStatus::kImplausibleTurn;
    e.sighting = sight(k, sets, gated ? &e.coast_agreement : nullptr);
    // A track seen missing, or that no ray reaches (out of view), drops: nothing seen holds it in
    // the air. Dropped, what the rays showed where it was says nothing of where it is now; an
    // unreached one stays hidden. Not when this frame's fit found its object (a fit the track
    // did not take: turned beyond the gate, or a lost track's that moved too far): something
    // seen holds it where that fit is, as when a hand carries it on.
    const bool missing = e.sighting == Sighting::kMissing;
    const bool unreached = e.fit.status == RefineStatus::kNotVisible;
    const bool fitted = gated || e.fit.status == RefineStatus::kOk;
    const bool dropped = (missing || unreached) && !fitted && options_.unseen_drop_m > 0.0 &&
                         dropsOutOfSight(k, sets);
    if (dropped && missing) e.sighting = Sighting::kThere, e.coast_agreement = -1.0;
  }
  weighPresence(evidence, uses, sets);
  for (std::size_t k : order)
    evidence[k].sunk =
        !evidence[k].child && sunkIntoMap(tracks_[k].out.class_name, tracks_[k].out.T_map_object);
}

void FramePipeline::weighPresence(std::vector<TrackEvidence>& evidence,
                                  const std::vector<FitUse>& uses,
                                  const std::vector<RangeMeasurements>& sets) {
  if (options_.confirm_presence_score <= 0.0) return;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Track& t = tracks_[k];
    // Only where it decides: a fit explaining too few of its rays is no hit anyway.
    if (t.life.state != TrackState::kTentative || uses[k] != FitUse::kUpdate ||
        evidence[k].fit.inlier_ratio < options_.confirm_inlier_ratio)
      continue;
    evidence[k].presence =  // presenceScore commits the scene before it casts
        presenceScore(scene_, t.out.node, catalog_->get(t.out.class_name).box, sets, noise_);
  }
}

}  // namespace sgt
