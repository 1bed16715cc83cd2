// Support found by rays: which surface an object rests on, for shapes that are not boxes. A grid
// of short rays goes straight down (world -z) from just above the object's lowest point into the
// ray-casting scene the tracker uses; a ray supports the node it first hits (the object's own
// instance is skipped) when that hit lies no more than max_gap below the object's lowest point,
// or when the ray leaves a solid there (the face's outward normal points down: the object has
// sunk into it, as tracked poses do by a millimetre or two; meshes are wound outward).
// A relay standing in a hollow KLT is thus supported by the KLT's floor although its box lies
// inside the KLT's box, not on its top: box relations say "in", the rays say "rests on the KLT".
#pragma once

#include <functional>
#include <limits>
#include <vector>

#include "scene_graph_tracker/relations/oriented_box.hpp"
#include "scene_graph_tracker/scene/node_id.hpp"

namespace sgt {
class RaycastScene;
}

namespace sgt::relations {

struct SupportOptions {
  int grid = 5;  // grid x grid rays over the object's footprint
  double footprint =
      0.8;             // share of the box's x / y extent (own frame) the grid spans; edges overhang
  double lift = 0.02;  // m, rays start this far above the lowest point (poses sink a little)
  double max_gap = 0.03;  // m, a hit farther below the lowest point supports nothing
  int self_skips = 3;     // times a ray may pass through the object's own mesh
};

struct Support {
  NodeId node = kNoNode;
  double fraction = 0.0;  // of all rays cast
  // m, mean of (lowest point - hit height) over its rays; a ray that starts inside the solid
  // counts min(0, lowest point - its origin), the depth it sank being unknown.
  double gap = std::numeric_limits<double>::infinity();
};

// Every node hit by supporting rays, most rays first. `self`: the object's own node in the scene
// (kNoNode when it has no instance there).
std::vector<Support> supportsBelow(const RaycastScene& scene, const OrientedBox& object,
                                   NodeId self = kNoNode, const SupportOptions& o = {});
// The same, the rays passing through every node for which `passes_through` holds as through the
// object's own (and through up to two more such solids): e.g. another track of the same object,
// or a track that takes no part in relations.
std::vector<Support> supportsBelow(const RaycastScene& scene, const OrientedBox& object,
                                   const std::function<bool(NodeId)>& passes_through,
                                   const SupportOptions& o = {});
// The node most rays rest on (node kNoNode, fraction 0 when none).
Support supportBelow(const RaycastScene& scene, const OrientedBox& object, NodeId self = kNoNode,
                     const SupportOptions& o = {});

}  // namespace sgt::relations
