#include "scene_graph_tracker/segmentation/depth_noise.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sgt {

std::optional<float> measureDepthSigmaAt1m(const RaycastScene& scene, const RangeMeasurements& m,
                                           float configured_sigma_at_1m,
                                           const DepthNoiseOptions& o) {
  const NodeId map = scene.staticMapNode();
  if (!m.isDepthImage() || map == kNoNode || m.size() == 0) return std::nullopt;
  const HitsLease lease = scratchHits(m.rays->width, m.rays->height);
  RayHits& hits = *lease;
  const TileSet tiles = TileSet::covering(
      *m.rays, std::vector<GridRect>{{0, 0, m.rays->width, m.rays->height}}, o.stride);
  scene.cast(*m.rays, m.T_world_sensor, hits, &tiles);
  const RangeTolerance window(o.min_window, o.window_sigmas * configured_sigma_at_1m);
  std::vector<float> scaled;  // |residual| / p^2
  tiles.forEachRay(*m.rays, [&](std::size_t i) {
    if (!m.valid(i) || hits.node[i] != map) return;
    const float p = hits.range[i], d = std::abs(m.range[i] - p);
    if (d < window.at(p)) scaled.push_back(d / (p * p));
  });
  if (static_cast<int>(scaled.size()) < std::max(1, o.min_rays)) return std::nullopt;
  const auto middle = scaled.begin() + scaled.size() / 2;
  std::nth_element(scaled.begin(), middle, scaled.end());
  return 1.4826f * *middle;
}

}  // namespace sgt
