#include "scene_graph_tracker/segmentation/presegmentation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

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
  const RangeTolerance tolerance(m, options.min_tolerance, options.noise, options.sigma_factor);
  // Every ray, so no stale hit is read; only what was hit where, and only up to where a surface
  // can still explain the measurement: a surface at p beyond r + 2 floor and r + 3 per_m2 r^2
  // lies farther than its own tolerance behind the point at r, so the point counts as unknown
  // with it or without it. That holds below r = 1 / (4 per_m2); a sensor that reaches farther
  // casts to the end.
  const bool bounded = m.rays->range_max * 4.0f * tolerance.per_m2 < 1.0f;
  const CastLimit limit{bounded ? &m.range : nullptr,
                        RangeTolerance(2.0f * tolerance.floor + 1e-4f, 3.0f * tolerance.per_m2)};
  scene.cast(*m.rays, m.T_world_sensor, hits, nullptr, limit, kRangeAndNodeOnly);
  const NodeId map = scene.staticMapNode();
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
