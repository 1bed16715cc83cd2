#include "scene_graph_tracker/registration/unexplained_pairs.hpp"

#include <algorithm>
#include <limits>

#include "scene_graph_tracker/registration/tile_order.hpp"

namespace sgt {

std::vector<std::vector<RayPair>> collectUnexplainedPairs(
    const RaycastScene& scene, const RangeMeasurements& m, const TileSet& tiles,
    const RayHits& hits, const NodeGroups& groups, const std::vector<ObjectExtent>& extents,
    const std::vector<MeshId>& meshes, const UnexplainedPairing& o) {
  const int n_obj = static_cast<int>(extents.size());
  std::vector<std::vector<RayPair>> out(n_obj);
  if (tiles.tiles().empty() || n_obj == 0) return out;
  std::vector<Eigen::Isometry3f> T_object_world(n_obj);
  std::vector<Eigen::AlignedBox3f> boxes(n_obj);
  for (int k = 0; k < n_obj; ++k) {
    T_object_world[k] = extents[k].T_world_object.inverse().cast<float>();
    boxes[k] = Eigen::AlignedBox3f(extents[k].box.min() - Eigen::Vector3f::Constant(o.box_margin),
                                   extents[k].box.max() + Eigen::Vector3f::Constant(o.box_margin));
  }
  const Eigen::Matrix3f R = m.T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f origin = m.T_world_sensor.translation().cast<float>();
  const SensorRays& rays = *m.rays;
  collectInTileOrder(tiles.tiles().size(), out, nullptr, [&](std::size_t b, auto& local, int*) {
    tiles.forTile(rays, b, [&](int, std::size_t i) {
      if (!m.valid(i)) return;
      const float r = m.range[i];
      if (groups(hits.node[i]) >= 0 && std::abs(hits.range[i] - r) < o.ray_threshold.at(r))
        return;  // ray pair
      if (!(hits.range[i] > r + o.front_margin))
        return;  // explained, or behind the predicted surface
      const Eigen::Vector3f ray_origin =
          rays.origins.empty() ? origin : Eigen::Vector3f(origin + R * rays.origins[i]);
      const Eigen::Vector3f p = ray_origin + R * (rays.directions[i] * r);
      int best = -1;
      float nearest = std::numeric_limits<float>::infinity();
      SurfacePoint closest{}, candidate{};
      for (int k = 0; k < n_obj; ++k) {
        const float radius = std::min(nearest, o.radii ? (*o.radii)[k] : o.radius);
        const Eigen::Vector3f q = T_object_world[k] * p;
        if (!(radius > 0.0f) || !boxes[k].contains(q) ||
            !scene.closestPoint(meshes[k], q, radius, candidate))
          continue;
        best = k, nearest = candidate.distance, closest = candidate;
      }
      if (best < 0) return;
      const Eigen::Isometry3d& T = extents[best].T_world_object;
      local[best].push_back({p, (T.cast<float>() * closest.point),
                             T.linear().cast<float>() * closest.normal,
                             static_cast<std::uint32_t>(i)});
    });
  });
  return out;
}

}  // namespace sgt
