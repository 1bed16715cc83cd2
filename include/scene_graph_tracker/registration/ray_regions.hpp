// Which rays of a sensor can see an object: the tiles of the ray grid covering the object's box
// (grown by a margin for the pose error) as the sensor sees it. Refinement casts only these.
#pragma once

#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"

namespace sgt {

struct ObjectExtent {
  Eigen::Isometry3d T_world_object;
  Eigen::AlignedBox3f box;  // object frame
};

// Grid rectangles of `m` that may see any of the objects, each box grown by `margin_m` on
// every side. Pinhole: projection of the corners; spinning LiDAR: azimuth / elevation span
// (split at the azimuth seam); other ray sets: rays passing the grown box's bounding sphere.
std::vector<GridRect> raysNearObjects(const RangeMeasurements& m,
                                      const std::vector<ObjectExtent>& objects, float margin_m);

}  // namespace sgt
