#include "scene_graph_tracker/segmentation/presegmentation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "scene_graph_tracker/segmentation/predicted_ranges.hpp"

namespace sgt {

const char* toString(PointLabel l) {
  switch (l) {
    case PointLabel::kInvalid:
      return "invalid";
    case PointLabel::kStaticMap:
      return "static map";
    case PointLabel::kObject:
      return "object";
    case PointLabel::kUnknown:
      return "unknown";
    case PointLabel::kBehind:
      return "behind the map";
  }
  return "?";
}

Presegmentation presegment(const RaycastScene& scene, const RangeMeasurements& m,
                           const PresegmentOptions& options) {
  Presegmentation out;
  const std::size_t n = m.size();
  out.label.assign(n, PointLabel::kInvalid);
  out.node.assign(n, kNoNode);
  if (n == 0) return out;
  const HitsLease lease = scratchHits(m.rays->width, m.rays->height);
  RayHits& hits = *lease;
  out.rays_cast =
      predictRanges(scene, m, hits, options.map_planes);  // every ray, so no stale hit is read
  const NodeId map = scene.staticMapNode();
  const RangeTolerance tolerance(m, options.min_tolerance, options.noise, options.sigma_factor);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (!m.valid(i)) continue;
      if (!hits.hit(i)) {
        out.label[i] = PointLabel::kUnknown;
        continue;
      }
      const float p = hits.range[i];
      const float tol = tolerance.at(p);
      const float d = m.range[i] - p;
      if (d < -tol) {
        out.label[i] = PointLabel::kUnknown;
      } else if (d > tol) {
        out.label[i] = PointLabel::kBehind;
      } else {
        out.label[i] = hits.node[i] == map ? PointLabel::kStaticMap : PointLabel::kObject;
        out.node[i] = hits.node[i];
      }
    }
  });
  const Eigen::Matrix3f R = m.T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f o = m.T_world_sensor.translation().cast<float>();
  for (std::size_t i = 0; i < n; ++i) {
    switch (out.label[i]) {
      case PointLabel::kInvalid:
        ++out.counts.invalid;
        break;
      case PointLabel::kStaticMap:
        ++out.counts.static_map;
        break;
      case PointLabel::kObject:
        ++out.counts.object;
        break;
      case PointLabel::kBehind:
        ++out.counts.behind;
        break;
      case PointLabel::kUnknown:
        ++out.counts.unknown;
        out.unknown_rays.push_back(static_cast<std::uint32_t>(i));
        out.unknown_points.push_back(
            (m.rays->origins.empty() ? o : Eigen::Vector3f(o + R * m.rays->origins[i])) +
            R * m.pointInSensor(i));
        break;
    }
  }
  return out;
}

}  // namespace sgt
