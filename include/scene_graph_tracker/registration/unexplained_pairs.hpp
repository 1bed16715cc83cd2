// Pull pairs for the measurements the ray cast leaves unexplained near an object.
//
// Ray-cast pairs see an object only where its model, at the current estimate, lies on the
// measured rays. A measured point of the object that the misplaced model misses (its ray passes
// beside the model and hits the map, or nothing, beyond the measurement) pairs with nothing, so a
// sideways error larger than the object's thickness (the thin screwdriver) or an aliasing rim
// (the KLT crate) leaves little to pull the model back. Such a point lies in front of the
// predicted surface; when it also lies near an object's box, it is paired with the closest point
// of that object's surface (Embree point query in the object frame): the ICP association, used
// only for what the sensor's own rays cannot explain.
#pragma once

#include <vector>

#include "scene_graph_tracker/registration/ray_correspondences.hpp"
#include "scene_graph_tracker/registration/ray_regions.hpp"

namespace sgt {

struct UnexplainedPairing {
  RangeTolerance ray_threshold;  // the round's ray-pair threshold: paired rays are explained
  float front_margin;  // a point counts as in front of the predicted surface beyond this (m)
  float box_margin;    // ... and as near an object within this of its box (m)
  float radius;        // largest distance to the object's surface that pairs (m)
  const std::vector<float>* radii = nullptr;  // per object, instead of `radius` (<= 0: no pulls)
};

// `hits` must hold the cast of `tiles` of `m` that collectRayPairs made with `groups` (object k
// is group k; `meshes[k]` its mesh, `extents[k]` its pose and box). Returns pull pairs per
// object: measured point, closest model point and its normal (world frame).
std::vector<std::vector<RayPair>> collectUnexplainedPairs(
    const RaycastScene& scene, const RangeMeasurements& m, const TileSet& tiles,
    const RayHits& hits, const NodeGroups& groups, const std::vector<ObjectExtent>& extents,
    const std::vector<MeshId>& meshes, const UnexplainedPairing& options);

}  // namespace sgt
