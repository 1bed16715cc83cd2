// FramePipeline: near twins weighed on the depth over frames (registration/twin_evidence.hpp).
#include <algorithm>

#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

namespace sgt {

const std::vector<Eigen::Isometry3d>& FramePipeline::twinsOf(const std::string& class_name) {
  auto it = class_twins_.find(class_name);
  if (it == class_twins_.end())
    it = class_twins_
             .emplace(class_name,
                      nearTwinTurns(scene_, class_mesh_.at(class_name), catalog_->get(class_name),
                                    options_.twin_max_surface_fraction))
             .first;
  return it->second;
}

void FramePipeline::weighTwins(const std::vector<RangeMeasurements>& sets) {
  const std::size_t n = tracks_.size();
  if (options_.twin_tests_per_frame <= 0 || n == 0 || sets.empty()) return;
  int tested = 0;
  std::size_t step = 0;
  for (; step < n && tested < options_.twin_tests_per_frame; ++step) {
    Track& t = tracks_[(twin_cursor_ + step) % n];
    // A track waiting for its orientation search is weighed once it has been searched.
    if (t.life.state != TrackState::kConfirmed || t.out.quality.status != RefineStatus::kOk ||
        std::find(needs_orientation_.begin(), needs_orientation_.end(), t.out.id) !=
            needs_orientation_.end())
      continue;
    const std::vector<Eigen::Isometry3d>& twins = twinsOf(t.out.class_name);
    if (twins.empty()) continue;
    if (t.twins.log_odds.size() != twins.size()) t.twins.reset(twins.size());
    const std::size_t k = t.twins.next % twins.size();
    const std::vector<Eigen::Isometry3d> poses{t.out.T_map_object, t.out.T_map_object * twins[k]};
    const TwinEvidence evidence = twinLogLikelihoodRatios(
        scene_, t.out.node, catalog_->get(t.out.class_name).box, poses, sets, noise_);
    ++tested;
    if (t.twins.update(t.out.T_map_object.linear(), k, evidence.z[1], options_.twin_frame_cap,
                       options_.twin_retain, options_.twin_switch_log_odds))
      turnToTwin(t, poses[1]);
  }
  twin_cursor_ = (twin_cursor_ + step) % n;
}

void FramePipeline::turnToTwin(Track& t, const Eigen::Isometry3d& T_map_object) {
  t.out.T_map_object = T_map_object;
  t.filter = PoseFilter(
      T_map_object, diagonalCovariance(options_.hypothesis_sigma_m, options_.hypothesis_sigma_rad),
      options_.motion);
  t.twins.reset(t.twins.log_odds.size());
  t.twins.R_world_object = T_map_object.linear();
  scene_.setInstancePose(t.out.node, T_map_object);
  scene_.commit();
  graph_.setWorldTransform(t.out.node, T_map_object);
}

}  // namespace sgt
