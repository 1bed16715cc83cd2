#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "scene_graph_tracker/segmentation/depth_noise.hpp"

namespace sgt {
namespace {

// Stage timing for process(): each stage runs through run() and its wall time goes to its field.
class StageClock {
 public:
  using Clock = std::chrono::steady_clock;
  template <typename F>
  void run(double& ms, F&& stage) {
    const auto t0 = Clock::now();
    stage();
    ms = msSince(t0);
  }
  double total() const { return msSince(start_); }

 private:
  static double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }
  Clock::time_point start_ = Clock::now();
};

}  // namespace

FramePipeline::FramePipeline(std::shared_ptr<const ObjectCatalog> catalog,
                             std::shared_ptr<const TriangleMesh> static_map,
                             const PipelineOptions& options)
    : catalog_(std::move(catalog)), options_(options), noise_(options.presegmentation.noise) {
  map_node_ = graph_.add("static_map", "static_map", kWorldNode, Eigen::Isometry3d::Identity());
  scene_.setStaticMap(std::move(static_map), map_node_);
  for (const std::string& name : catalog_->names()) {
    const auto& mesh = catalog_->get(name).mesh;
    class_mesh_[name] = scene_.addMesh(mesh);
    const std::size_t step =
        std::max<std::size_t>(1, mesh->vertices.size() / 64);  // up to ~64 vertices
    for (std::size_t i = 0; i < mesh->vertices.size(); i += step)
      class_samples_[name].push_back(mesh->vertices[i]);
  }
  scene_.commit();
}

PipelineResult FramePipeline::process(PipelineFrame frame) {
  StageClock clock;
  PipelineResult out;
  out.stamp = frame.stamp;
  std::vector<RangeMeasurements>& sets = frame.measurements;
  // 1. Localize the robot against the static map; every sensor moves with the correction.
  clock.run(out.times.localize_ms, [&] {
    localize(frame, out);
    measureNoise(sets);
  });
  out.noise = noise_;
  // 2. Predict the tracks to this frame and assign the hypotheses to them.
  clock.run(out.times.associate_ms, [&] {
    predict(frame.stamp);
    const auto accepted = acceptedHypotheses(frame.hypotheses, out.hypotheses_over_limits);
    associate(accepted, frame.stamp, out);
    scene_.commit();
  });
  // 3. Refine every track from its prediction, then advance the track life cycles.
  clock.run(out.times.refine_ms, [&] { refineTracks(objectSets(sets), frame.stamp, out.dropped); });
  // 4. Relations among the tracks and the furniture, and re-parenting.
  clock.run(out.times.relations_ms, [&] {
    if (options_.compute_relations) updateRelations(out, sets);
  });
  // 5. Pre-segment every measurement against the map and the tracks that explain points.
  clock.run(out.times.presegment_ms, [&] {
    if (options_.run_presegmentation) out.presegmentation = presegmentAll(sets);
  });
  out.objects = snapshot();
  out.measurements = std::move(sets);
  out.times.total_ms = clock.total();
  return out;
}

void FramePipeline::localize(PipelineFrame& frame, PipelineResult& out) {
  // The prior is the last map -> odom correction composed with the odometry.
  std::vector<RangeMeasurements>& sets = frame.measurements;
  for (RangeMeasurements& m : sets) m.T_world_sensor = T_map_odom_ * m.T_world_sensor;
  const Eigen::Isometry3d prior = T_map_odom_ * frame.T_odom_base;
  const std::vector<RangeMeasurements> for_localization = localizationSets(sets);
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
}

void FramePipeline::measureNoise(const std::vector<RangeMeasurements>& sets) {
  if (!options_.measure_depth_noise) return;
  // A frame moves the estimate by a fifth of its difference: a few frames settle it, a frame in
  // which a person fills the view does not.
  constexpr float kWeight = 0.2f;
  for (const RangeMeasurements& m : sets)
    if (const auto s =
            measureDepthSigmaAt1m(scene_, m, options_.presegmentation.noise.depth_sigma_at_1m))
      noise_.depth_sigma_at_1m += kWeight * (*s - noise_.depth_sigma_at_1m);
}

void FramePipeline::setOptions(const PipelineOptions& o) {
  const RangeNoise& before = options_.presegmentation.noise;
  if (o.presegmentation.noise.depth_sigma_at_1m != before.depth_sigma_at_1m ||
      o.presegmentation.noise.range_sigma != before.range_sigma || !o.measure_depth_noise)
    noise_ = o.presegmentation.noise;  // a new setting starts the measurement again
  if (o.twin_max_surface_fraction != options_.twin_max_surface_fraction) class_twins_.clear();
  options_ = o;
}

RefinerOptions FramePipeline::withSensorNoise(RefinerOptions r) const {
  r.noise = noise_, r.noise_sigmas = options_.refiner.noise_sigmas;
  return r;
}

std::vector<RangeMeasurements> FramePipeline::localizationSets(
    const std::vector<RangeMeasurements>& sets) const {
  std::vector<RangeMeasurements> chosen;
  for (const RangeMeasurements& m : sets)
    if (!options_.localize_with_lidar_only || !m.isDepthImage()) chosen.push_back(m);
  return chosen;
}

std::vector<RangeMeasurements> FramePipeline::objectSets(
    const std::vector<RangeMeasurements>& sets) const {
  // Depth images when the frame has one; LiDAR returns too only with refine_with_lidar.
  const bool has_depth = std::any_of(sets.begin(), sets.end(), [](const RangeMeasurements& m) {
    return std::holds_alternative<PinholeModel>(m.model);
  });
  std::vector<RangeMeasurements> chosen;
  for (const RangeMeasurements& m : sets)
    if (options_.refine_with_lidar || !has_depth || std::holds_alternative<PinholeModel>(m.model))
      chosen.push_back(m);
  return chosen;
}

std::vector<PoseHypothesis> FramePipeline::acceptedHypotheses(
    const std::vector<PoseHypothesis>& hypotheses, std::size_t& over_limit) const {
  std::vector<PoseHypothesis> accepted;
  for (const PoseHypothesis& h : hypotheses)
    if (h.score >= options_.min_hypothesis_score && catalog_->contains(h.class_name) &&
        h.T_base_object.matrix().allFinite())
      accepted.push_back(h);
  const std::size_t limit =
      static_cast<std::size_t>(std::max(0, options_.max_hypotheses_per_frame));
  if (accepted.size() <= limit) return accepted;
  // The best-scored `limit`, in their order.
  std::vector<std::size_t> order(accepted.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return accepted[a].score > accepted[b].score;
  });
  order.resize(limit);
  std::sort(order.begin(), order.end());
  std::vector<PoseHypothesis> best;
  for (std::size_t i : order) best.push_back(accepted[i]);
  over_limit += accepted.size() - limit;
  return best;
}

void FramePipeline::refineTracks(const std::vector<RangeMeasurements>& sets, double stamp,
                                 std::vector<std::string>& dropped) {
  if (options_.contest_restarts && !sets.empty()) contestRestarts(sets);
  for (Track& t : tracks_) t.before_restart.reset();
  if (!sets.empty()) settleDisputes(sets, stamp);
  if (options_.search_orientations && !sets.empty())
    searchOrientations(sets, stamp);
  else
    needs_orientation_.clear();
  if (tracks_.empty() || sets.empty()) return;
  std::vector<RefineTarget> targets;
  for (const Track& t : tracks_) {
    RefineTarget target{t.out.node, &catalog_->get(t.out.class_name).symmetry};
    // A confirmed track's pulls reach as far as it may have moved: the largest standard deviation
    // of its predicted position, times pull_sigmas. A tentative one is not established yet (it
    // may be a false detection on something unknown): it pulls fully.
    if (options_.pull_sigmas > 0.0 && t.life.state != TrackState::kTentative) {
      const Eigen::Matrix3d P = t.filter.covariance().topLeftCorner<3, 3>();
      const double sigma = std::sqrt(
          std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P, Eigen::EigenvaluesOnly)
                            .eigenvalues()
                            .maxCoeff()));
      target.pull_radius = static_cast<float>(options_.pull_sigmas * sigma);
    }
    // The fit weighs its rays against the track's prediction (not a child's: its filter does not
    // follow its parent).
    if (options_.refiner.prior_weight > 0.0 && !isChild(t.out.node)) {
      target.T_prior = t.filter.pose();
      target.prior_information = t.filter.poseCovariance().inverse();
    }
    targets.push_back(target);
  }
  RefinerOptions refiner = withSensorNoise(options_.refiner);
  refiner.information = options_.fit_point_sigma_m > 0.0;  // only weighted fits read it
  const RefineResult r = ObjectRefiner(refiner).refine(scene_, targets, sets);
  updateTracks(r, sets, stamp, dropped);
  scene_.commit();
  weighTwins(sets);
}

std::vector<Presegmentation> FramePipeline::presegmentAll(
    const std::vector<RangeMeasurements>& sets) {
  // Only tracks that explain points stay in the scene (PresegmentationRole).
  std::vector<NodeId> hidden;
  for (const Track& t : tracks_)
    if (!PresegmentationRole::explainsPoints(t.life.state, unsupported(t)))
      hidden.push_back(t.out.node), scene_.setInstanceEnabled(t.out.node, false);
  if (!hidden.empty()) scene_.commit();
  std::vector<Presegmentation> result;
  PresegmentOptions presegmentation = options_.presegmentation;
  presegmentation.noise = noise_;
  for (const RangeMeasurements& m : sets) result.push_back(presegment(scene_, m, presegmentation));
  for (NodeId n : hidden) scene_.setInstanceEnabled(n, true);
  if (!hidden.empty()) scene_.commit();
  return result;
}

std::vector<TrackedObject> FramePipeline::snapshot() const {
  std::vector<TrackedObject> objects;
  for (const Track& t : tracks_) {
    TrackedObject o = t.out;
    o.state = t.life.state;
    o.hits = t.life.hits;
    o.detections = t.life.detections;
    o.last_hypothesis = t.life.last_hypothesis;
    o.parent = trackIdOf(graph_.node(t.out.node).parent);
    o.orientation_confidence = t.twins.confidence();
    objects.push_back(std::move(o));
  }
  return objects;
}

std::string FramePipeline::addTrack(const std::string& class_name,
                                    const Eigen::Isometry3d& T_map_object, double stamp) {
  return startTrack(class_name, T_map_object, stamp, {});
}

std::string FramePipeline::startTrack(const std::string& class_name,
                                      const Eigen::Isometry3d& T_map_object, double stamp,
                                      const std::string& id) {
  if (!catalog_->contains(class_name))
    throw std::invalid_argument("no class '" + class_name + "' in the catalog");
  const auto C = diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad);
  Track t{TrackedObject{}, TrackLife{}, PoseFilter(T_map_object, C, options_.motion)};
  TrackedObject& o = t.out;
  o.class_name = class_name;
  o.id = !id.empty() ? id : class_name + "_" + std::to_string(++class_count_[class_name]);
  o.node = graph_.add(o.id, class_name, kWorldNode, T_map_object);
  o.T_map_object = T_map_object;
  o.covariance = C;
  o.first_seen = t.life.last_hypothesis = stamp;
  t.life.detections = options_.confirm_detections;  // by hand: trusted like a detected object
  if (options_.twin_tests_per_frame > 0) t.twins.reset(twinsOf(class_name).size());
  t.twins.R_world_object = T_map_object.linear();
  scene_.addInstance(o.node, class_mesh_.at(class_name), T_map_object);
  scene_.commit();
  tracks_.push_back(std::move(t));
  return tracks_.back().out.id;
}

bool FramePipeline::removeTrack(const std::string& id) {
  for (std::size_t k = 0; k < tracks_.size(); ++k)
    if (tracks_[k].out.id == id) {
      dropTrack(k);
      scene_.commit();
      return true;
    }
  return false;
}

void FramePipeline::dropTrack(std::size_t k) {
  hysteresis_.forget(tracks_[k].out.id);
  scene_.removeInstance(tracks_[k].out.node);
  graph_.remove(tracks_[k].out.node);
  tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(k));
}

void FramePipeline::reset() {
  while (!tracks_.empty()) removeTrack(tracks_.back().out.id);
  T_map_odom_ = Eigen::Isometry3d::Identity();
  noise_ = options_.presegmentation.noise;
  last_stamp_ = -1.0;
  hysteresis_.clear();
  unlocated_.clear();
}

void FramePipeline::continueTrackNumbers(const std::map<std::string, int>& last) {
  for (const auto& [name, n] : last) class_count_[name] = std::max(class_count_[name], n);
}

void FramePipeline::setTracksEnabled(bool enabled) {
  for (const Track& t : tracks_) scene_.setInstanceEnabled(t.out.node, enabled);
  scene_.commit();
}

}  // namespace sgt
