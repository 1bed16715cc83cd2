#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

namespace sgt {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

FramePipeline::FramePipeline(std::shared_ptr<const ObjectCatalog> catalog, std::shared_ptr<const TriangleMesh> static_map,
                             const PipelineOptions& options)
    : catalog_(std::move(catalog)), options_(options) {
  map_node_ = graph_.add("static_map", "static_map", kWorldNode, Eigen::Isometry3d::Identity());
  scene_.setStaticMap(std::move(static_map), map_node_);
  for (const std::string& name : catalog_->names()) class_mesh_[name] = scene_.addMesh(catalog_->get(name).mesh);
  scene_.commit();
}

NodeId FramePipeline::addObject(const std::string& class_name, const Eigen::Isometry3d& T_map_object, double stamp) {
  KnownObject o;
  o.class_name = class_name;
  o.id = class_name + "_" + std::to_string(++class_count_[class_name]);
  o.node = graph_.add(o.id, class_name, kWorldNode, T_map_object);
  o.T_map_object = T_map_object;
  o.first_seen = o.last_hypothesis = stamp;
  scene_.addInstance(o.node, class_mesh_.at(class_name), T_map_object);
  objects_.push_back(o);
  return o.node;
}

void FramePipeline::dropObject(std::size_t index, std::vector<std::string>& dropped) {
  dropped.push_back(objects_[index].id);
  scene_.removeInstance(objects_[index].node);
  graph_.remove(objects_[index].node);
  objects_.erase(objects_.begin() + static_cast<std::ptrdiff_t>(index));
}

void FramePipeline::associate(const std::vector<PoseHypothesis>& hypotheses, const Eigen::Isometry3d& T_map_base,
                              double stamp) {
  // Greedy by distance over (hypothesis, object) pairs of one class: each object takes at most
  // one hypothesis per frame.
  struct Candidate {
    double distance;
    std::size_t hypothesis, object;
  };
  std::vector<Candidate> candidates;
  std::vector<Eigen::Isometry3d> in_map(hypotheses.size());
  for (std::size_t h = 0; h < hypotheses.size(); ++h) {
    in_map[h] = T_map_base * hypotheses[h].T_base_object;
    for (std::size_t k = 0; k < objects_.size(); ++k) {
      if (objects_[k].class_name != hypotheses[h].class_name) continue;
      const double d = (objects_[k].T_map_object.translation() - in_map[h].translation()).norm();
      if (d < options_.association_distance) candidates.push_back({d, h, k});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.distance < b.distance; });
  std::vector<char> hyp_used(hypotheses.size(), 0), obj_used(objects_.size(), 0);
  for (const Candidate& c : candidates) {
    if (hyp_used[c.hypothesis] || obj_used[c.object]) continue;
    hyp_used[c.hypothesis] = obj_used[c.object] = 1;
    KnownObject& o = objects_[c.object];
    o.last_hypothesis = stamp;
    if (o.quality.status != RefineStatus::kOk) {  // lost its fit: start again from the detection
      o.T_map_object = in_map[c.hypothesis];
      scene_.setInstancePose(o.node, o.T_map_object);
    }
  }
  for (std::size_t h = 0; h < hypotheses.size(); ++h)
    if (!hyp_used[h]) addObject(hypotheses[h].class_name, in_map[h], stamp);
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
    out.localization = localizer.localize(scene_, for_localization, prior);
    out.localized = out.localization.status == LocalizeStatus::kOk;
    if (out.localized) {
      const Eigen::Isometry3d correction = out.localization.T_map_base * prior.inverse();
      T_map_odom_ = correction * T_map_odom_;
      for (RangeMeasurements& m : sets) m.T_world_sensor = correction * m.T_world_sensor;
    }
  }
  out.T_map_odom = T_map_odom_;
  out.T_map_base = T_map_odom_ * frame.T_odom_base;
  out.times.localize_ms = msSince(t0);

  // 2. Hypotheses -> known objects.
  t0 = Clock::now();
  std::vector<PoseHypothesis> accepted;
  for (const PoseHypothesis& h : frame.hypotheses)
    if (h.score >= options_.min_hypothesis_score && catalog_->contains(h.class_name)) accepted.push_back(h);
  associate(accepted, out.T_map_base, frame.stamp);
  scene_.commit();
  out.times.associate_ms = msSince(t0);

  // 3. Refine every known object against all measurements of the frame.
  t0 = Clock::now();
  std::vector<RefineTarget> targets;
  for (const KnownObject& o : objects_) targets.push_back({o.node, &catalog_->get(o.class_name).symmetry});
  std::vector<RangeMeasurements> for_objects;
  const bool has_depth = std::any_of(sets.begin(), sets.end(), [](const RangeMeasurements& m) {
    return std::holds_alternative<PinholeModel>(m.model);
  });
  for (const RangeMeasurements& m : sets)
    if (options_.refine_with_lidar || !has_depth || std::holds_alternative<PinholeModel>(m.model)) for_objects.push_back(m);
  if (!targets.empty() && !for_objects.empty()) {
    const ObjectRefiner refiner(options_.refiner);
    const RefineResult r = refiner.refine(scene_, targets, for_objects);
    for (std::size_t k = 0; k < objects_.size(); ++k) {
      KnownObject& o = objects_[k];
      o.quality = r.objects[k].quality;
      o.T_map_object = r.objects[k].T_world_object;
      graph_.setWorldTransform(o.node, o.T_map_object);
      const bool failed = o.quality.status == RefineStatus::kFalseHypothesis;
      o.failed_frames = failed ? o.failed_frames + 1 : 0;
    }
    for (std::size_t k = objects_.size(); k-- > 0;)
      if (objects_[k].failed_frames >= options_.drop_after_failed_frames) dropObject(k, out.dropped);
    scene_.commit();
  }
  out.times.refine_ms = msSince(t0);

  // 4. Pre-segment every measurement against the map and the refined objects.
  t0 = Clock::now();
  if (options_.run_presegmentation)
    for (const RangeMeasurements& m : sets) out.presegmentation.push_back(presegment(scene_, m, options_.presegmentation));
  out.times.presegment_ms = msSince(t0);

  out.objects = objects_;
  out.measurements = std::move(sets);
  out.times.total_ms = msSince(t_frame);
  return out;
}

}  // namespace sgt
