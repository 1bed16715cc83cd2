// Which rays of a sensor can see an object: the tiles of the ray grid covering the object's box
// (grown by a margin for the pose error) as the sensor sees it. Refinement casts only these.
#pragma once

#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/sensors/range_noise.hpp"

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

// How sampleRaysNearObjects picks each object's rays.
struct RaySampling {
  float margin_m = 0.0f;                        // each box grows by this on every side ...
  const std::vector<float>* margins = nullptr;  // ... or, when given, by its own (per object)
  int stride = 1;                               // every stride-th ray in x and y
  // A depth image (pinhole) object's region is sampled at the smallest stride (any integer, not
  // only powers of two) at which it holds at most this many rays (0: no bound), so that a near
  // object costs what a far one does and the count stays near the bound.
  int max_rays = 0;
  const std::vector<char>* skip = nullptr;  // objects whose entry is set get no region
  // Per object, how many rays of the `stride` sampling reach it (negative: unknown): where known,
  // that count, not the region's, is what max_rays bounds.
  const std::vector<double>* on_object = nullptr;
};

// The rays near each object (raysNearObjects). weight[k] is how many rays of the `stride`
// sampling each cast ray near object k stands for: (its stride / stride)^2.
struct ObjectSampling {
  std::vector<SampledRect> regions;
  std::vector<float> weight;  // per object
};
ObjectSampling sampleRaysNearObjects(const RangeMeasurements& m,
                                     const std::vector<ObjectExtent>& objects,
                                     const RaySampling& sampling);

// Whether a ray of `m` can pair with one of the objects: its measurement is valid and either its
// measured point lies within the object's box grown by the object's margin (it may pull the
// object), or its cast, which ends at the measured range r plus `cast_slack.at(r)`, can reach
// the box (it may hit the object). A ray for which neither holds pairs with nothing, so a
// refinement that skips it gets the same pairs for fewer casts.
class PairableRays {
 public:
  // `margins` per object; objects whose `skip` entry is set (may be null) are left out.
  PairableRays(const RangeMeasurements& m, const std::vector<ObjectExtent>& objects,
               const std::vector<float>& margins, const std::vector<char>* skip,
               const RangeTolerance& cast_slack);
  bool operator()(std::size_t ray) const;

 private:
  struct Target {
    Eigen::Matrix3f R;  // sensor -> object
    Eigen::Vector3f t;
    Eigen::AlignedBox3f hit_box, pull_box;
    std::vector<GridRect> rects;  // the grid cells near it (raysNearObjects)
  };
  const RangeMeasurements& m_;
  RangeTolerance slack_;
  std::vector<Target> targets_;
};

}  // namespace sgt
