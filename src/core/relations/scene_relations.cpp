#include "scene_graph_tracker/relations/scene_relations.hpp"

#include <algorithm>
#include <set>

#include "scene_graph_tracker/scene/raycast_scene.hpp"

namespace sgt::relations {
namespace {

constexpr Relation kDirections[] = {Relation::LeftOf, Relation::RightOf, Relation::InFrontOf,
                                    Relation::Behind, Relation::Above,   Relation::Below};

double lowest(const OrientedBox& b) {
  double z = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : corners(b)) z = std::min(z, c.z());
  return z;
}
double highest(const OrientedBox& b) {
  double z = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : corners(b)) z = std::max(z, c.z());
  return z;
}

}  // namespace

std::vector<Edge> sceneRelations(const std::vector<Entity>& entities, const RaycastScene* scene,
                                 NodeId map_node, const SceneRelationOptions& o,
                                 const std::optional<Eigen::Isometry3d>& T_world_camera) {
  auto duplicates = [](const Entity& a, const Entity& b) {
    return a.movable && b.movable && !a.kind.empty() && a.kind == b.kind &&
           intersects(a.box, b.box);
  };
  std::set<NodeId> entity_nodes;  // of the tracked objects
  for (const Entity& e : entities)
    if (e.movable) entity_nodes.insert(e.node);
  std::vector<Edge> out;
  for (const Entity& t : entities) {
    if (!t.movable) continue;
    std::set<NodeId> twins;  // nodes of t's duplicates, judged once per t
    for (const Entity& r : entities)
      if (&r != &t && duplicates(t, r)) twins.insert(r.node);
    // What the rays say t rests on (kNoNode: nothing, or no scene to cast into). They pass
    // through t itself, its duplicates and what is no entity (a tentative track).
    NodeId rests_on = kNoNode;
    if (scene) {
      auto passes = [&](NodeId n) {
        return n == t.node || (n != map_node && (!entity_nodes.count(n) || twins.count(n)));
      };
      const std::vector<Support> all = supportsBelow(*scene, t.box, passes, o.support);
      if (!all.empty() && all.front().fraction >= o.min_support) rests_on = all.front().node;
    }
    for (const Entity& r : entities) {
      if (&r == &t || (r.movable && twins.count(r.node))) continue;
      const NodeId r_node = r.movable ? r.node : map_node;
      const bool rests_on_r = rests_on != kNoNode && rests_on == r_node;
      const bool in =
          r.movable && (contains(r.box, t.box, o.box.tolerance) ||
                        (rests_on_r && intersects(r.box, t.box) && lowest(t.box) < highest(r.box)));
      // With rays, "on" needs contact: something held 1 cm over a crate's rim is not on it.
      const bool box_on = holds(Relation::On, Mode::Relaxed, t.box, r.box, o.box);
      const bool on = scene ? rests_on_r && (r.movable || box_on) : box_on;
      if (in || on) out.push_back({t.name, in ? Relation::In : Relation::On, r.name});
      if (!o.directional || !r.movable) continue;
      for (Relation d : kDirections) {
        const bool h =
            o.camera_relative && T_world_camera
                ? holdsFromViewpoint(d, o.directional_mode, t.box, r.box, *T_world_camera, o.box)
                : holds(d, o.directional_mode, t.box, r.box, o.box);
        if (h) out.push_back({t.name, d, r.name});
      }
    }
  }
  // Support is one-way: two boxes each "on" or "in" the other (duplicate tracks of one object)
  // say nothing about either.
  auto supports = [](const Edge& e) {
    return e.relation == Relation::On || e.relation == Relation::In;
  };
  auto mutual = [&](const Edge& e) {
    return supports(e) && std::any_of(out.begin(), out.end(), [&](const Edge& f) {
             return supports(f) && f.subject == e.object && f.object == e.subject;
           });
  };
  std::vector<Edge> kept;
  for (const Edge& e : out)
    if (!mutual(e)) kept.push_back(e);
  return kept;
}

}  // namespace sgt::relations
