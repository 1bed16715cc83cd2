#include "scene_graph_tracker/relations/support_rays.hpp"

#include <algorithm>
#include <map>

#include "scene_graph_tracker/scene/raycast_scene.hpp"

namespace sgt::relations {
namespace {

// Whether ray i left the solid it hit: the face's outward normal (meshes are wound outward)
// points along the ray, so the ray started inside that solid.
bool leaves(const RaycastScene& scene, const RayHits& hits, std::size_t i,
            const Eigen::Vector3f& direction) {
  const NodeId node = hits.node[i];
  if (!scene.hasInstance(node)) return false;
  const TriangleMesh& m = scene.mesh(scene.instanceMesh(node));
  const Triangle& t = m.triangles[hits.primitive[i]];
  const Eigen::Vector3f n =
      (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
  return (scene.instancePose(node).linear().cast<float>() * n).dot(direction) > 0.0f;
}

// Ray origins: a grid over the box's footprint (own x / y), `lift` above its lowest point.
std::vector<WorldRay> gridRays(const OrientedBox& object, double bottom, const SupportOptions& o,
                               float far) {
  const int n = std::max(1, o.grid);
  const Eigen::Vector3d& h = object.half_extents;
  std::vector<WorldRay> rays;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = n == 1 ? 0.0 : 2.0 * i / (n - 1) - 1.0,
                   v = n == 1 ? 0.0 : 2.0 * j / (n - 1) - 1.0;
      Eigen::Vector3d p = object.T_world_box *
                          Eigen::Vector3d(u * o.footprint * h.x(), v * o.footprint * h.y(), 0.0);
      p.z() = bottom + o.lift;
      rays.push_back({p.cast<float>(), -Eigen::Vector3f::UnitZ(), far});
    }
  return rays;
}

// `other_solids`: solids besides its own that a ray may pass through (two passes each, in and out).
std::vector<Support> castSupportRays(const RaycastScene& scene, const OrientedBox& object,
                                     const std::function<bool(NodeId)>& passes_through,
                                     int other_solids, const SupportOptions& o) {
  double bottom = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& c : corners(object)) bottom = std::min(bottom, c.z());
  // Rays reach far enough to leave a solid they start in (an object sunk into a table top).
  constexpr float kReach = 0.5f, kStep = 1e-4f;
  std::vector<WorldRay> rays = gridRays(object, bottom, o, static_cast<float>(o.lift) + kReach);
  const double cast_count = static_cast<double>(rays.size());
  std::map<NodeId, std::pair<int, double>> by_node;  // rays, summed gap
  RayHits hits;
  for (int round = 0; round <= o.self_skips + 2 * other_solids && !rays.empty(); ++round) {
    scene.cast(rays, hits);
    std::vector<WorldRay> again;  // rays that hit the object itself continue below that hit
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (!hits.hit(i)) continue;
      const float z = hits.point[i].z();
      if (passes_through(hits.node[i])) {
        const float rest = rays[i].far - (rays[i].origin.z() - z) - kStep;
        if (rest > 0.0f)
          again.push_back({hits.point[i] - Eigen::Vector3f(0, 0, kStep), rays[i].direction, rest});
        continue;
      }
      double gap = bottom - z;
      if (leaves(scene, hits, i, rays[i].direction)) {
        gap = std::min(0.0,
                       bottom - rays[i].origin.z());  // started inside it: sunk in, depth unknown
      } else if (gap > o.max_gap) {
        continue;
      }
      auto& [count, gap_sum] = by_node[hits.node[i]];
      ++count;
      gap_sum += gap;
    }
    rays = std::move(again);
  }
  std::vector<Support> out;
  for (const auto& [node, value] : by_node)
    out.push_back({node, value.first / cast_count, value.second / value.first});
  std::sort(out.begin(), out.end(),
            [](const Support& a, const Support& b) { return a.fraction > b.fraction; });
  return out;
}

}  // namespace

std::vector<Support> supportsBelow(const RaycastScene& scene, const OrientedBox& object,
                                   NodeId self, const SupportOptions& o) {
  return castSupportRays(
      scene, object, [self](NodeId n) { return n == self; }, 0, o);
}

std::vector<Support> supportsBelow(const RaycastScene& scene, const OrientedBox& object,
                                   const std::function<bool(NodeId)>& passes_through,
                                   const SupportOptions& o) {
  return castSupportRays(scene, object, passes_through, 2, o);
}

Support supportBelow(const RaycastScene& scene, const OrientedBox& object, NodeId self,
                     const SupportOptions& o) {
  const std::vector<Support> all = supportsBelow(scene, object, self, o);
  return all.empty() ? Support{} : all.front();
}

}  // namespace sgt::relations
