// Identifiers of scene-graph nodes, shared by the scene graph and the ray-casting scene.
#pragma once

#include <cstdint>

namespace sgt {

using NodeId = std::int32_t;
constexpr NodeId kNoNode = -1;    // "no node": a ray that hit nothing, an unassigned point
constexpr NodeId kWorldNode = 0;  // the scene graph's root, the map frame

}  // namespace sgt
