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

namespace {

// A measurement's label against the range `hits` predicts along its ray.
PointLabel labelOf(const RangeMeasurements& m, const RayHits& hits, std::size_t i,
                   const RangeTolerance& tolerance, NodeId map) {
  if (!m.valid(i)) return PointLabel::kInvalid;
  if (!hits.hit(i)) return PointLabel::kUnknown;
  const float p = hits.range[i];
  const float tol = tolerance.at(p);
  const float d = m.range[i] - p;
  if (d < -tol) return PointLabel::kUnknown;
  if (d > tol) return PointLabel::kBehind;
  return hits.node[i] == map ? PointLabel::kStaticMap : PointLabel::kObject;
}

// The labels of a run of rays: their counts and unknown points, merged in ray order afterwards.
struct LabelRun {
  LabelCounts counts;
  std::vector<std::uint32_t> unknown_rays;
  std::vector<Eigen::Vector3f> unknown_points;
};

void count(PointLabel l, LabelCounts& c) {
  switch (l) {
    case PointLabel::kInvalid:
      ++c.invalid;
      break;
    case PointLabel::kStaticMap:
      ++c.static_map;
      break;
    case PointLabel::kObject:
      ++c.object;
      break;
    case PointLabel::kBehind:
      ++c.behind;
      break;
    case PointLabel::kUnknown:
      ++c.unknown;
      break;
  }
}

void merge(std::vector<LabelRun>& runs, Presegmentation& out) {
  for (LabelRun& r : runs) {
    out.counts.invalid += r.counts.invalid, out.counts.static_map += r.counts.static_map;
    out.counts.object += r.counts.object, out.counts.behind += r.counts.behind;
    out.counts.unknown += r.counts.unknown;
    out.unknown_rays.insert(out.unknown_rays.end(), r.unknown_rays.begin(), r.unknown_rays.end());
    out.unknown_points.insert(out.unknown_points.end(), r.unknown_points.begin(),
                              r.unknown_points.end());
  }
}

}  // namespace

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
  const Eigen::Matrix3f R = m.T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f o = m.T_world_sensor.translation().cast<float>();
  constexpr std::size_t kRun = 4096;
  std::vector<LabelRun> runs((n + kRun - 1) / kRun);
  tbb::parallel_for(std::size_t{0}, runs.size(), [&](std::size_t k) {
    LabelRun& run = runs[k];
    for (std::size_t i = k * kRun; i < std::min(n, (k + 1) * kRun); ++i) {
      const PointLabel l = labelOf(m, hits, i, tolerance, map);
      out.label[i] = l;
      count(l, run.counts);
      if (l == PointLabel::kStaticMap || l == PointLabel::kObject) out.node[i] = hits.node[i];
      if (l != PointLabel::kUnknown) continue;
      run.unknown_rays.push_back(static_cast<std::uint32_t>(i));
      run.unknown_points.push_back(
          (m.rays->origins.empty() ? o : Eigen::Vector3f(o + R * m.rays->origins[i])) +
          R * m.pointInSensor(i));
    }
  });
  merge(runs, out);
  return out;
}

}  // namespace sgt
