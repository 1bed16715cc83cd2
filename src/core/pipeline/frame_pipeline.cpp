#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "scene_graph_tracker/tracking/assignment.hpp"

namespace sgt {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

const char* toString(TrackState s) {
  switch (s) {
    case TrackState::kTentative: return "tentative";
    case TrackState::kConfirmed: return "confirmed";
    case TrackState::kLost: return "lost";
    case TrackState::kRemoved: return "removed";
  }
  return "?";
}

FramePipeline::FramePipeline(std::shared_ptr<const ObjectCatalog> catalog, std::shared_ptr<const TriangleMesh> static_map,
                             const PipelineOptions& options)
    : catalog_(std::move(catalog)), options_(options) {
  map_node_ = graph_.add("static_map", "static_map", kWorldNode, Eigen::Isometry3d::Identity());
  scene_.setStaticMap(std::move(static_map), map_node_);
  for (const std::string& name : catalog_->names()) {
    const auto& mesh = catalog_->get(name).mesh;
    class_mesh_[name] = scene_.addMesh(mesh);
    const std::size_t step = std::max<std::size_t>(1, mesh->vertices.size() / 64);  // up to ~64 vertices
    for (std::size_t i = 0; i < mesh->vertices.size(); i += step) class_samples_[name].push_back(mesh->vertices[i]);
  }
  scene_.commit();
}

std::string FramePipeline::addTrack(const std::string& class_name, const Eigen::Isometry3d& T_map_object, double stamp) {
  if (!catalog_->contains(class_name)) throw std::invalid_argument("no class '" + class_name + "' in the catalog");
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  Track t{TrackedObject{}, PoseFilter(T_map_object, C, options_.motion)};
  TrackedObject& o = t.out;
  o.class_name = class_name;
  o.id = class_name + "_" + std::to_string(++class_count_[class_name]);
  o.node = graph_.add(o.id, class_name, kWorldNode, T_map_object);
  o.T_map_object = T_map_object;
  o.covariance = C;
  o.first_seen = o.last_hypothesis = stamp;
  o.detections = options_.confirm_detections;  // by hand: trusted like a detected object
  scene_.addInstance(o.node, class_mesh_.at(class_name), T_map_object);
  scene_.commit();
  tracks_.push_back(std::move(t));
  return tracks_.back().out.id;
}

bool FramePipeline::removeTrack(const std::string& id) {
  for (std::size_t k = 0; k < tracks_.size(); ++k)
    if (tracks_[k].out.id == id) {
      hysteresis_.forget(id);
      scene_.removeInstance(tracks_[k].out.node);
      scene_.commit();
      graph_.remove(tracks_[k].out.node);
      tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(k));
      return true;
    }
  return false;
}

void FramePipeline::reset() {
  while (!tracks_.empty()) removeTrack(tracks_.back().out.id);
  T_map_odom_ = Eigen::Isometry3d::Identity();
  last_stamp_ = -1.0;
  hysteresis_.clear();
}

void FramePipeline::setTracksEnabled(bool enabled) {
  for (const Track& t : tracks_) scene_.setInstanceEnabled(t.out.node, enabled);
  scene_.commit();
}

void FramePipeline::predict(double stamp) {
  const double dt = last_stamp_ >= 0.0 ? stamp - last_stamp_ : 0.0;
  last_stamp_ = stamp;
  for (Track& t : tracks_) {
    if (dt > 0.0 && t.out.quality.status != RefineStatus::kOk) t.filter.damp(dt);  // coasting
    if (dt > 0.0) t.filter.predict(dt);
  }
  // A track under the world follows its filter; a child keeps its pose relative to its parent
  // (moved just before it), so what is in or on a carried object is carried along.
  for (std::size_t k : parentsFirst()) {
    Track& t = tracks_[k];
    if (!isChild(t.out.node)) graph_.setWorldTransform(t.out.node, t.filter.pose());
    t.out.T_map_object = graph_.worldTransform(t.out.node);
    scene_.setInstancePose(t.out.node, t.out.T_map_object);
  }
}

std::vector<std::size_t> FramePipeline::parentsFirst() const {
  std::vector<std::pair<int, std::size_t>> by_depth;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    int depth = 0;
    for (NodeId n = tracks_[k].out.node; graph_.node(n).parent != kWorldNode; n = graph_.node(n).parent) ++depth;
    by_depth.emplace_back(depth, k);
  }
  std::sort(by_depth.begin(), by_depth.end());
  std::vector<std::size_t> order;
  for (const auto& [depth, k] : by_depth) order.push_back(k);
  return order;
}

void FramePipeline::associate(const std::vector<PoseHypothesis>& hypotheses, const Eigen::Isometry3d& T_map_base,
                              double stamp) {
  const double forbidden = std::numeric_limits<double>::max();
  Eigen::MatrixXd cost(hypotheses.size(), tracks_.size());
  std::vector<Eigen::Isometry3d> in_map(hypotheses.size());
  for (std::size_t h = 0; h < hypotheses.size(); ++h) {
    in_map[h] = T_map_base * hypotheses[h].T_base_object;
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      const TrackedObject& o = tracks_[k].out;
      const double d = (o.T_map_object.translation() - in_map[h].translation()).norm();
      // A track whose fit failed may have moved unseen: wider gate. Not a child: it is where
      // its parent holds it (a relay hidden in a crate), and a detection of its class farther
      // away is another object or a false one (in the demo, one pulled the relay out of the KLT).
      const bool child = isChild(o.node);
      const double gate = o.quality.status == RefineStatus::kOk || child ? options_.association_distance
                                                                          : options_.reacquire_distance;
      cost(h, k) = o.class_name == hypotheses[h].class_name && d < gate ? d : forbidden;
    }
  }
  const std::vector<int> match = assignMinCost(cost, forbidden);
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  for (std::size_t h = 0; h < hypotheses.size(); ++h) {
    if (match[h] < 0) {
      addTrack(hypotheses[h].class_name, in_map[h], stamp);
      tracks_.back().out.detections = 1;
      continue;
    }
    Track& t = tracks_[match[h]];
    t.out.last_hypothesis = stamp;
    ++t.out.detections;
    // Lost its fit: start again from the detection (unless a weak fit placed it: min_weak_fit_inliers).
    if (t.out.quality.status != RefineStatus::kOk && !placedByWeakFit(t)) {
      if (t.out.state == TrackState::kLost) t.before_restart = t.filter;
      t.filter.update(in_map[h], C, &catalog_->get(t.out.class_name).symmetry);
      t.out.T_map_object = in_map[h];
      scene_.setInstancePose(t.out.node, in_map[h]);
      needs_orientation_.push_back(t.out.id);
    }
  }
}

void FramePipeline::updateTracks(const RefineResult& r, const std::vector<RangeMeasurements>& sets, double stamp,
                                 std::vector<std::string>& dropped) {
  const auto C = diagonalCovariance(options_.refined_sigma_m, options_.refined_sigma_rad);
  const auto C_follow = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  std::vector<std::size_t> coasting;     // confirmed tracks without a fit this frame
  for (std::size_t k : parentsFirst()) {  // a coasting child follows its parent's new pose
    Track& t = tracks_[k];
    TrackedObject& o = t.out;
    o.quality = r.objects[k].quality;
    // A lost track (hidden, or its fits failed) stays where it was lost unless a detection
    // restarts it or it is seen whole again: a fit that moves it far fitted something else (in
    // the demo, the edge of the box hiding the screwdriver, 10 cm away), and one that explains
    // only part of its rays is a glimpse past the occluder, which pulled the screwdriver by 2 cm.
    const bool resumes_unaided = o.state == TrackState::kLost && o.last_hypothesis < stamp;
    const bool jumped = o.quality.status == RefineStatus::kOk && resumes_unaided &&
                        ((r.objects[k].T_world_object.translation() - o.T_map_object.translation()).norm() >
                             options_.lost_track_max_jump_m ||
                         o.quality.inlier_ratio < options_.lost_track_resume_inlier_ratio);
    const bool child = isChild(o.node);
    // A tentative track's fit from too few points that explains most of its rays places it
    // (min_weak_fit_inliers): no hit, no fit support, but the next frame starts from there.
    if (placedByWeakFit(t)) {
      t.filter = PoseFilter(r.objects[k].T_world_object, C_follow, options_.motion);
      o.T_map_object = r.objects[k].T_world_object;
      t.absent_since = -1.0;
    } else if (o.quality.status == RefineStatus::kOk && !jumped) {
      // A fit from few points or from far away is a weaker measurement (fitWeakness), and the
      // track reports the filtered pose rather than that frame's fit (the screwdriver at 2.5 m:
      // ~40 inliers, fits jumping by 1-2 cm). Not for a child: its filter does not follow its
      // parent's motion.
      const double weak = child ? 1.0 : fitWeakness(o, sets);
      t.filter.update(r.objects[k].T_world_object, C * weak, &catalog_->get(o.class_name).symmetry);
      o.T_map_object = weak > 1.0 ? t.filter.pose() : r.objects[k].T_world_object;
      o.last_refined = stamp;
      const double ratio = o.quality.inlier_ratio;
      t.fit_support = t.fit_support < 0.0 ? ratio : t.fit_support + options_.fit_support_weight * (ratio - t.fit_support);
      // A confirmed track whose good fits keep leaving most of its rays unexplained (they pass
      // through the model to what lies behind) is no object there. Not a child: its fits are
      // cut by its parent.
      if (o.state == TrackState::kTentative || !unsupported(t)) t.absent_since = -1.0;
      else if (t.absent_since < 0.0) t.absent_since = stamp;
      // A tentative track's fit counts towards confirmation only when it explains most of the
      // rays that reach the model: a detection on something else (the walking person, in the
      // detector demo) lets a model fit a patch of it, but then explains 35-50 % of its rays.
      if (o.state != TrackState::kTentative || o.quality.inlier_ratio >= options_.confirm_inlier_ratio) ++o.hits;
      const bool confirmed = o.hits >= options_.confirm_hits && o.detections >= options_.confirm_detections &&
                             t.fit_support >= options_.min_fit_support;
      if (confirmed && o.state == TrackState::kTentative)
        needs_orientation_.push_back(o.id);  // a real object now: is its rotation the right one?
      // A confirmed track whose fits keep leaving a share of its rays unexplained may be turned
      // (research_below_fit_support): it is searched again, every orientation_search_interval_s.
      if (o.state == TrackState::kConfirmed && !child && t.fit_support < options_.research_below_fit_support &&
          stamp - t.last_orientation_search >= options_.orientation_search_interval_s &&
          std::find(needs_orientation_.begin(), needs_orientation_.end(), o.id) == needs_orientation_.end())
        needs_orientation_.push_back(o.id);
      if (confirmed || o.state == TrackState::kLost) o.state = TrackState::kConfirmed;
    } else {
      // Coast on the prediction. Evidence of absence: the object should show points (rays reach
      // it) but hardly any agree with it; hidden or out-of-view objects have none expected.
      // A child (in / on another track) is hidden by its parent more than the rays know (a relay
      // deep in a crate) and its pose is only the parent's: it collects no evidence of absence.
      if (child) t.filter.update(graph_.worldTransform(o.node), C_follow, &catalog_->get(o.class_name).symmetry);
      o.T_map_object = child ? graph_.worldTransform(o.node) : t.filter.pose();
      if (child) {
        t.absent_since = -1.0;
      } else if (o.state == TrackState::kTentative) {
        // From the failed refinement's quality (quick, for false detections). A degenerate fit
        // (planar inliers) is no evidence when the object shows what it should, but it is when
        // those few inliers are all it shows: a thing taken from a table leaves a handful of
        // table points along its former bottom edge, in one plane.
        const bool should_show = o.quality.expected >= options_.refiner.alignment.min_points;
        const bool explained = o.quality.inlier_ratio >= options_.refiner.min_inlier_ratio;
        const bool absent = should_show && (o.quality.status != RefineStatus::kDegenerate || !explained);
        if (!absent) t.absent_since = -1.0;
        else if (t.absent_since < 0.0) t.absent_since = stamp;
      } else {
        coasting.push_back(k);  // judged below, at the pose it coasts at (seeAbsence)
      }
      if (o.state == TrackState::kConfirmed) o.state = TrackState::kLost;
    }
    o.covariance = t.filter.poseCovariance();
    scene_.setInstancePose(o.node, o.T_map_object);
    graph_.setWorldTransform(o.node, o.T_map_object);
  }
  if (!coasting.empty()) {
    scene_.commit();
    for (std::size_t k : coasting) {
      Track& t = tracks_[k];
      if (!seesAbsence(k, sets)) t.absent_since = -1.0;
      else if (t.absent_since < 0.0) t.absent_since = stamp;
    }
  }
  for (Track& t : tracks_) {
    if (isChild(t.out.node) || !sunkIntoMap(t.out.class_name, t.out.T_map_object)) t.sunk_since = -1.0;
    else if (t.sunk_since < 0.0) t.sunk_since = stamp;
  }
  for (std::size_t k = tracks_.size(); k-- > 0;) {
    Track& t = tracks_[k];
    const double limit =
        t.out.state == TrackState::kTentative ? options_.remove_tentative_after_s : options_.remove_after_s;
    // A tentative track that detections stopped confirming goes too, seen or not (a false
    // positive out of the sensors' reach never collects evidence of absence).
    const bool stale = t.out.state == TrackState::kTentative &&
                       stamp - t.out.last_hypothesis > options_.tentative_timeout_s;
    const bool sunk = t.sunk_since >= 0.0 && stamp - t.sunk_since >= limit;
    if (!stale && !sunk && (t.absent_since < 0.0 || stamp - t.absent_since < limit)) continue;
    dropped.push_back(t.out.id);
    hysteresis_.forget(t.out.id);
    scene_.removeInstance(t.out.node);
    graph_.remove(t.out.node);
    tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(k));
  }
}

PipelineResult FramePipeline::process(PipelineFrame frame) {
  const auto t_frame = Clock::now();
  PipelineResult out;
  out.stamp = frame.stamp;
  // 1. Localize: the prior is the last map -> odom correction composed with the odometry.
  auto t0 = Clock::now();
  std::vector<RangeMeasurements>& sets = frame.measurements;
  for (RangeMeasurements& m : sets) m.T_world_sensor = T_map_odom_ * m.T_world_sensor;
  const Eigen::Isometry3d prior = T_map_odom_ * frame.T_odom_base;
  std::vector<RangeMeasurements> for_localization;
  for (const RangeMeasurements& m : sets)
    if (!options_.localize_with_lidar_only || std::holds_alternative<SpinningLidarModel>(m.model))
      for_localization.push_back(m);
  if (options_.localize && !for_localization.empty()) {
    const Localizer localizer(options_.localizer);
    if (!options_.localize_against_objects) setTracksEnabled(false);
    out.localization = localizer.localize(scene_, for_localization, prior);
    if (!options_.localize_against_objects) setTracksEnabled(true);
    out.localized = out.localization.status == LocalizeStatus::kOk;
    if (out.localized) {
      const Eigen::Isometry3d correction = out.localization.T_map_base * prior.inverse();
      T_map_odom_ = rigid(correction * T_map_odom_);
      for (RangeMeasurements& m : sets) m.T_world_sensor = correction * m.T_world_sensor;
    }
  }
  out.T_map_odom = T_map_odom_;
  out.T_map_base = T_map_odom_ * frame.T_odom_base;
  out.times.localize_ms = msSince(t0);

  // 2. Predict the tracks to this frame and assign the hypotheses to them.
  t0 = Clock::now();
  predict(frame.stamp);
  std::vector<PoseHypothesis> accepted;
  for (const PoseHypothesis& h : frame.hypotheses)
    if (h.score >= options_.min_hypothesis_score && catalog_->contains(h.class_name)) accepted.push_back(h);
  associate(accepted, out.T_map_base, frame.stamp);
  scene_.commit();
  out.times.associate_ms = msSince(t0);

  // 3. Refine every track from its prediction, then update the filters and the track states.
  t0 = Clock::now();
  std::vector<RangeMeasurements> for_objects;
  const bool has_depth = std::any_of(sets.begin(), sets.end(), [](const RangeMeasurements& m) {
    return std::holds_alternative<PinholeModel>(m.model);
  });
  for (const RangeMeasurements& m : sets)
    if (options_.refine_with_lidar || !has_depth || std::holds_alternative<PinholeModel>(m.model)) for_objects.push_back(m);
  if (options_.contest_restarts && !for_objects.empty()) contestRestarts(for_objects);
  for (Track& t : tracks_) t.before_restart.reset();
  if (options_.search_orientations && !for_objects.empty()) searchOrientations(for_objects, frame.stamp);
  else needs_orientation_.clear();
  if (!tracks_.empty() && !for_objects.empty()) {
    std::vector<RefineTarget> targets;
    for (const Track& t : tracks_) targets.push_back({t.out.node, &catalog_->get(t.out.class_name).symmetry});
    const RefineResult r = ObjectRefiner(options_.refiner).refine(scene_, targets, for_objects);
    updateTracks(r, for_objects, frame.stamp, out.dropped);
    scene_.commit();
  }
  out.times.refine_ms = msSince(t0);
  t0 = Clock::now();
  if (options_.compute_relations) updateRelations(out, sets);
  out.times.relations_ms = msSince(t0);

  // 4. Pre-segment every measurement against the map and the tracked objects. Tentative tracks
  // (one detection, not yet confirmed) explain nothing: a false detection on an unknown thing
  // would hide it, and a real new object is confirmed within a few frames. Neither do tracks
  // whose recent fits the measurements contradict (fit support below min_fit_support; not a
  // child, whose fits its parent cuts): they are on their way out, and what they cover is most
  // likely the unknown thing they sit on.
  t0 = Clock::now();
  if (options_.run_presegmentation) {
    std::vector<NodeId> hidden;
    for (const Track& t : tracks_)
      if (t.out.state == TrackState::kTentative || unsupported(t))
        hidden.push_back(t.out.node), scene_.setInstanceEnabled(t.out.node, false);
    if (!hidden.empty()) scene_.commit();
    for (const RangeMeasurements& m : sets) out.presegmentation.push_back(presegment(scene_, m, options_.presegmentation));
    for (NodeId n : hidden) scene_.setInstanceEnabled(n, true);
    if (!hidden.empty()) scene_.commit();
  }
  out.times.presegment_ms = msSince(t0);

  for (const Track& t : tracks_) {
    out.objects.push_back(t.out);
    out.objects.back().parent = trackIdOf(graph_.node(t.out.node).parent);
  }
  out.measurements = std::move(sets);
  out.times.total_ms = msSince(t_frame);
  return out;
}

}  // namespace sgt
