#include "scene_graph_tracker/segmentation/predicted_ranges.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "scene_graph_tracker/registration/ray_regions.hpp"

namespace sgt {
namespace {

constexpr float kPlaneTolerance = 1e-3f;  // m: a corner's hit off the first corner's plane
constexpr float kNormalCos = 0.9998f;     // about 1.1 deg between the corners' normals
constexpr float kMinIncidence = 0.05f;    // |cos| of a corner ray to the plane's normal
constexpr float kObjectMargin = 0.01f;    // m around an object's box: its hits' rounding

// Blocks of 4 x 4 pixels, the cast's tiles; block (bx, by) spans pixels [4 bx, 4 (bx + 1)] in x
// and likewise in y, corners included (neighbours share their edges).
struct BlockGrid {
  static constexpr int size = 4;
  int cols, rows;
  explicit BlockGrid(const SensorRays& rays)
      : cols((rays.width - 1) / size), rows((rays.height - 1) / size) {}
  std::size_t count() const { return static_cast<std::size_t>(cols) * rows; }
  // Whether block (bx, by)'s rays are cast (its fill is 0, kCast).
  bool casts(const std::vector<char>& fills, int bx, int by) const {
    return fills[static_cast<std::size_t>(by) * cols + bx] == 0;
  }
};

// The blocks whose rays may see an enabled object instance (every instance but the static map).
std::vector<char> blocksNearObjects(const RaycastScene& scene, const RangeMeasurements& m,
                                    const BlockGrid& g) {
  std::vector<ObjectExtent> objects;
  for (const NodeId n : scene.enabledInstances())
    if (n != scene.staticMapNode())
      objects.push_back({scene.instancePose(n), scene.meshBox(scene.instanceMesh(n))});
  std::vector<char> near(g.count(), 0);
  for (const GridRect& r : raysNearObjects(m, objects, kObjectMargin)) {
    const int bx1 = std::min(g.cols - 1, (r.x1 - 1) / g.size);
    const int by1 = std::min(g.rows - 1, (r.y1 - 1) / g.size);
    for (int by = std::max(0, (r.y0 - 1) / g.size); by <= by1; ++by)
      for (int bx = std::max(0, (r.x0 - 1) / g.size); bx <= bx1; ++bx)
        near[static_cast<std::size_t>(by) * g.cols + bx] = 1;
  }
  return near;
}

std::array<std::size_t, 4> cornersOf(const SensorRays& rays, const BlockGrid& g, int bx, int by) {
  const int x = bx * g.size, y = by * g.size;
  return {static_cast<std::size_t>(rays.index(x, y)),
          static_cast<std::size_t>(rays.index(x + g.size, y)),
          static_cast<std::size_t>(rays.index(x, y + g.size)),
          static_cast<std::size_t>(rays.index(x + g.size, y + g.size))};
}

// Whether the four corner rays hit the static map on one plane that each meets well off grazing.
bool seesOnePlane(const RayHits& h, const std::array<std::size_t, 4>& c, NodeId map,
                  const SensorRays& rays, const Eigen::Matrix3f& R) {
  const Eigen::Vector3f& n = h.normal[c[0]];
  for (const std::size_t i : c) {
    if (h.node[i] != map || h.normal[i].dot(n) < kNormalCos) return false;
    if (std::abs(n.dot(h.point[i] - h.point[c[0]])) > kPlaneTolerance) return false;
    if (-n.dot(R * rays.directions[i]) < kMinIncidence) return false;  // normals face the rays
  }
  return true;
}

// How a block's rays other than its corners get their ranges: cast, from the plane its corners
// see, or none (its corners see nothing: no part of the map the size of a block is in it).
enum BlockFill : char { kCast = 0, kPlane = 1, kEmpty = 2 };

// Ranges for the pixels a block owns ([size bx, size (bx + 1)) in x and y, the last block of a row
// or column up to its far edge) as its fill says; its corners keep their cast.
void fillBlock(const SensorRays& rays, const BlockGrid& g, int bx, int by, BlockFill fill,
               const Eigen::Vector3f& origin, const Eigen::Matrix3f& R, NodeId map,
               const std::array<std::size_t, 4>& c, RayHits& h) {
  const bool plane = fill == kPlane;  // else kEmpty: the corners' normals are not theirs
  const Eigen::Vector3f n = plane ? h.normal[c[0]] : Eigen::Vector3f::UnitZ();
  const float offset = plane ? n.dot(h.point[c[0]] - origin) : 0.0f;
  const Eigen::Vector3f n_sensor = R.transpose() * n;
  const int x1 = (bx + 1) * g.size - (bx + 1 < g.cols ? 1 : 0);
  const int y1 = (by + 1) * g.size - (by + 1 < g.rows ? 1 : 0);
  for (int y = by * g.size; y <= y1; ++y)
    for (int x = bx * g.size; x <= x1; ++x) {
      if (x % g.size == 0 && y % g.size == 0) continue;
      const std::size_t i = static_cast<std::size_t>(rays.index(x, y));
      const float r = plane ? offset / n_sensor.dot(rays.directions[i]) : -1.0f;
      const bool within = r >= rays.range_min && r <= rays.range_max;  // as a cast would end
      h.range[i] = within ? r : std::numeric_limits<float>::infinity();
      h.node[i] = within ? map : kNoNode;
    }
}

// The blocks whose closed span holds pixel coordinate v: one, or two on a shared edge.
std::pair<int, int> blocksAt(int v, int size, int count) {
  const int b = v / size;
  return {std::max(0, v % size == 0 ? b - 1 : b), std::min(b, count - 1)};
}

// Whether pixel (x, y) is cast ray by ray: beyond the whole blocks, or in a block not filled from
// a plane or found empty. The corners are cast on their own.
bool castAlone(int x, int y, const BlockGrid& g, const std::vector<char>& fills) {
  if (x > g.cols * g.size || y > g.rows * g.size) return true;
  if (x % g.size == 0 && y % g.size == 0) return false;
  const auto [bx0, bx1] = blocksAt(x, g.size, g.cols);
  const auto [by0, by1] = blocksAt(y, g.size, g.rows);
  for (int by = by0; by <= by1; ++by)
    for (int bx = bx0; bx <= bx1; ++bx)
      if (g.casts(fills, bx, by)) return true;
  return false;
}

// The lanes of the tile of pixels [4 tx, 4 tx + 3] x [4 ty, 4 ty + 3] to cast (castAlone): inside
// the blocks, those of its own block if that is cast, else the shared left column and top row where
// the neighbour there is cast; never the corner.
std::uint16_t lanesToCast(const SensorRays& rays, const TileSet::Tile& t, const BlockGrid& g,
                          const std::vector<char>& fills) {
  const int tx = t.x0 / g.size, ty = t.y0 / g.size;
  if (tx == 0 || ty == 0 || tx >= g.cols || ty >= g.rows) {
    std::uint16_t lanes = 0;
    for (int k = 0; k < 16; ++k)
      if (t.x0 + k % 4 < rays.width && t.y0 + k / 4 < rays.height &&
          castAlone(t.x0 + k % 4, t.y0 + k / 4, g, fills))
        lanes |= static_cast<std::uint16_t>(1u << k);
    return lanes;
  }
  if (g.casts(fills, tx, ty)) return 0xfffe;
  constexpr std::uint16_t kLeftColumn = 0x1110, kTopRow = 0x000e;
  return static_cast<std::uint16_t>((g.casts(fills, tx - 1, ty) ? kLeftColumn : 0) |
                                    (g.casts(fills, tx, ty - 1) ? kTopRow : 0));
}

// Decides each block's fill and fills it: from a plane where its corners see one of the map, none
// where they see nothing; cast where its rays may see an object, or its corners see more than one
// surface. A fill writes only the block's own pixels, never a corner, so blocks go in parallel.
std::vector<char> fillBlocks(const RaycastScene& scene, const RangeMeasurements& m,
                             const BlockGrid& g, RayHits& hits) {
  const Eigen::Matrix3f R = m.T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f origin = m.T_world_sensor.translation().cast<float>();
  const NodeId map = scene.staticMapNode();
  const std::vector<char> near = blocksNearObjects(scene, m, g);
  std::vector<char> fills(g.count(), kCast);
  tbb::parallel_for(0, g.rows, [&](int by) {
    for (int bx = 0; bx < g.cols; ++bx) {
      const std::size_t b = static_cast<std::size_t>(by) * g.cols + bx;
      const auto c = cornersOf(*m.rays, g, bx, by);
      if (near[b]) continue;
      if (std::none_of(c.begin(), c.end(), [&](std::size_t i) { return hits.hit(i); }))
        fills[b] = kEmpty;
      else if (seesOnePlane(hits, c, map, *m.rays, R))
        fills[b] = kPlane;
      if (fills[b] != kCast)
        fillBlock(*m.rays, g, bx, by, static_cast<BlockFill>(fills[b]), origin, R, map, c, hits);
    }
  });
  return fills;
}

}  // namespace

std::size_t predictRanges(const RaycastScene& scene, const RangeMeasurements& m, RayHits& hits,
                          bool from_planes) {
  const SensorRays& rays = *m.rays;
  const bool blocks = from_planes && std::holds_alternative<PinholeModel>(m.model) &&
                      rays.origins.empty() && scene.staticMapNode() != kNoNode &&
                      rays.width > BlockGrid::size && rays.height > BlockGrid::size;
  if (!blocks) {
    scene.cast(rays, m.T_world_sensor, hits, nullptr, {}, kRangeAndNodeOnly);
    return rays.size();
  }
  const BlockGrid g(rays);
  TileSet corners =
      TileSet::sampled(rays, {{GridRect{0, 0, rays.width, rays.height}, BlockGrid::size}});
  scene.cast(rays, m.T_world_sensor, hits, &corners, {}, kHitPoint | kHitNormal);
  const std::vector<char> fills = fillBlocks(scene, m, g, hits);
  TileSet rest = TileSet::all(rays);
  rest.keepLanes([&](const TileSet::Tile& t) { return lanesToCast(rays, t, g, fills); });
  scene.cast(rays, m.T_world_sensor, hits, &rest, {}, kRangeAndNodeOnly);
  return corners.rayCount() + rest.rayCount();
}

}  // namespace sgt
