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

// The rays near each object (raysNearObjects) sampled at `stride`, coarsened for a depth image
// (pinhole) object by powers of two until its region holds at most `max_rays` rays (0: no bound),
// so that a near object costs what a far one does. weight[k] is how many rays of the `stride`
// sampling each cast ray near object k stands for: (its stride / stride)^2. Objects whose
// `skip` entry is set (when given) get no region.
struct ObjectSampling {
  std::vector<SampledRect> regions;
  std::vector<float> weight;  // per object
};
ObjectSampling sampleRaysNearObjects(const RangeMeasurements& m,
                                     const std::vector<ObjectExtent>& objects, float margin_m,
                                     int stride, int max_rays,
                                     const std::vector<char>* skip = nullptr);

}  // namespace sgt
