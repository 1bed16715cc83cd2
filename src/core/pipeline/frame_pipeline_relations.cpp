// FramePipeline's relation step: relations among tracks and furniture, hysteresis, re-parenting.
#include "scene_graph_tracker/pipeline/frame_pipeline.hpp"

namespace sgt {

std::string FramePipeline::trackIdOf(NodeId node) const {
  for (const Track& t : tracks_)
    if (t.out.node == node) return t.out.id;
  return "";
}

void FramePipeline::updateRelations(PipelineResult& out,
                                    const std::vector<RangeMeasurements>& sets) {
  std::vector<relations::Entity> entities = furniture_;
  for (const Track& t : tracks_) {
    if (t.life.state == TrackState::kTentative) continue;
    const Eigen::AlignedBox3d box = catalog_->get(t.out.class_name).box.cast<double>();
    entities.push_back({t.out.id, t.out.node, relations::orientedBox(box, t.out.T_map_object), true,
                        t.out.class_name});
  }
  std::optional<Eigen::Isometry3d> camera;
  for (const RangeMeasurements& m : sets)
    if (std::holds_alternative<PinholeModel>(m.model)) camera = m.T_world_sensor;
  const std::vector<relations::Edge> now =
      relations::sceneRelations(entities, &scene_, map_node_, options_.relation_options, camera);
  hysteresis_.setOptions(options_.relation_hysteresis);
  out.relations = hysteresis_.update(now);
  if (options_.reparent) reparent(out.relations);
}

void FramePipeline::reparent(const std::vector<relations::Edge>& edges) {
  for (const Track& t : tracks_) {
    // "in" wins over "on"; the parent must be a track (furniture is part of the static map).
    NodeId parent = kWorldNode;
    for (relations::Relation kind : {relations::Relation::In, relations::Relation::On}) {
      for (const relations::Edge& e : edges) {
        if (parent != kWorldNode || e.subject != t.out.id || e.relation != kind) continue;
        for (const Track& p : tracks_)
          if (p.out.id == e.object && !graph_.isAncestor(t.out.node, p.out.node))
            parent = p.out.node;
      }
    }
    if (graph_.node(t.out.node).parent != parent) graph_.reparent(t.out.node, parent);
  }
}

}  // namespace sgt
