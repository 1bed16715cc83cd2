// Pre-segmentation of the unknown: after localization and refinement, every valid measurement is
// explained by the static map, by a known object, or by nothing the tracker knows. The unknown
// points are what a later detector should look at (the paper: a VLP-16 scan went from 25,287
// points to 3,515, -86 %).
//
// Each measurement's range r is compared with the range p that the scene at the current estimates
// predicts along its ray (cast, or on a plane of the static map its neighbours' casts found): |r -
// p| <= tolerance(p) (from the sensor's noise) -> the hit's owner (map or object); r < p -
// tolerance -> unknown (something stands in front of what the tracker knows); r > p + tolerance ->
// behind (the map changed, e.g. a door was opened); no predicted hit -> unknown.
#pragma once

#include <vector>

#include "scene_graph_tracker/scene/raycast_scene.hpp"
#include "scene_graph_tracker/sensors/range_measurements.hpp"
#include "scene_graph_tracker/sensors/range_noise.hpp"

namespace sgt {

enum class PointLabel : std::uint8_t { kInvalid, kStaticMap, kObject, kUnknown, kBehind };
const char* toString(PointLabel l);

struct PresegmentOptions {
  // A measurement agrees with the predicted surface within sigma_factor x its noise sigma (at the
  // predicted range p; sensors/range_noise.hpp), and never less than min_tolerance (map and mesh
  // modelling error).
  float sigma_factor = 3.0f;
  float min_tolerance = 0.02f;
  RangeNoise noise;
  // On a depth image, the predicted ranges of blocks of 4 x 4 pixels that see one plane of the
  // static map come from that plane instead of a cast per ray (segmentation/predicted_ranges.hpp).
  bool map_planes = true;
};

struct LabelCounts {
  std::size_t invalid = 0, static_map = 0, object = 0, unknown = 0, behind = 0;
  std::size_t valid() const { return static_map + object + unknown + behind; }
  // Share of the valid measurements that are not unknown (the paper's -86 % is 0.86).
  double reduction() const { return valid() ? 1.0 - static_cast<double>(unknown) / valid() : 0.0; }
};

struct Presegmentation {
  std::vector<PointLabel> label;  // per ray
  std::vector<NodeId>
      node;  // per ray: the object or map node for kObject / kStaticMap, else kNoNode
  std::vector<Eigen::Vector3f> unknown_points;  // world frame
  std::vector<std::uint32_t> unknown_rays;      // ray index of each unknown point
  LabelCounts counts;
  std::size_t rays_cast = 0;  // rays cast to predict the ranges
};

// Hits of the scene's static map node count as map, hits of any other instance as object.
Presegmentation presegment(const RaycastScene& scene, const RangeMeasurements& m,
                           const PresegmentOptions& options = {});

}  // namespace sgt
