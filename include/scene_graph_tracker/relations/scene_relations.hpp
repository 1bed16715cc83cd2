// The relations that hold among the things a tracker knows in one frame: tracked objects (movable,
// with an instance in the ray-casting scene) and static furniture (reference boxes only, e.g. a
// workbench top, read by relations/furniture.hpp). Rules on top of spatial_relations.hpp and
// support_rays.hpp:
//   in(T, R):  R's box contains T's (tolerance box.tolerance), or T rests by rays on R while
//              its box intersects R's and its lowest point lies below R's top (a relay standing
//              on the floor of a KLT and sticking out above the rim).
//   on(T, R):  not in(T, R), and T rests by rays on R (share of rays >= min_support: contact, so
//              an object held just over a crate is not on it); for furniture, which is part of the
//              static map, T rests on the map and the relaxed box "on" holds (R's top projection
//              intersects T, distance < on_max_distance). So a relay in a KLT on the bench is in
//              the KLT, not on the bench. Without a scene (boxes only): the relaxed box "on".
//   on / in are one-way: when T and R each stand on or in the other (two tracks of one object),
//              neither edge is kept.
//   Two tracked objects of one kind whose boxes intersect are one object tracked twice (one of
//              the tracks off): no relation between them, and T's support rays pass through R,
//              as through any scene node that is no entity (a tentative track).
//   left_of, right_of, in_front_of, behind, above, below: among tracked objects only, with
//              directional_mode (strict: projection contains; relaxed: halfspace intersects), in
//              R's own frame or, with camera_relative, from the camera's point of view.
// T is always a tracked object; R a tracked object or furniture.
#pragma once

#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "scene_graph_tracker/relations/spatial_relations.hpp"
#include "scene_graph_tracker/relations/support_rays.hpp"

namespace sgt {
class RaycastScene;
}

namespace sgt::relations {

struct Entity {
  std::string name;       // track id, or the furniture's name
  NodeId node = kNoNode;  // its instance in the ray-casting scene; kNoNode for furniture
  OrientedBox box;
  bool movable = true;  // false: furniture, a reference only
  std::string kind;     // class name of a tracked object ("": unknown, never a duplicate)
};

// "subject relation object", e.g. relay_1 in klt_1.
struct Edge {
  std::string subject;
  Relation relation = Relation::On;
  std::string object;
  bool operator<(const Edge& o) const {
    return std::tie(subject, relation, object) < std::tie(o.subject, o.relation, o.object);
  }
  bool operator==(const Edge& o) const {
    return subject == o.subject && relation == o.relation && object == o.object;
  }
};

struct SceneRelationOptions {
  RelationOptions box{3.5, 0.02,
                      0.01};  // factor, on_max_distance, tolerance (tracked poses are noisy)
  SupportOptions support;
  double min_support = 0.3;  // share of rays that makes "rests on"
  bool directional = true;   // compute left_of ... below among tracked objects
  Mode directional_mode = Mode::Strict;
  bool camera_relative = false;  // directions from the camera's point of view
};

// The instantaneous relations among `entities`. `scene` (may be null: boxes only) holds the tracked
// objects' instances; `map_node` is the static map's node there (resting on it = resting on the
// furniture); `T_world_camera` (optical frame) is needed for camera_relative.
std::vector<Edge> sceneRelations(
    const std::vector<Entity>& entities, const RaycastScene* scene, NodeId map_node,
    const SceneRelationOptions& o = {},
    const std::optional<Eigen::Isometry3d>& T_world_camera = std::nullopt);

}  // namespace sgt::relations
