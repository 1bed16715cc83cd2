// TileSet: regions sampled at their own strides (each ray cast once, the finer sampling wins where
// they overlap) and phases that shift a sampled grid so that successive casts see other rays.
#include <gtest/gtest.h>

#include <set>

#include "scene_graph_tracker/scene/tile_set.hpp"
#include "support.hpp"

namespace sgt {
namespace {

SensorRays grid(int width, int height) {
  PinholeModel cam;
  cam.width = width, cam.height = height, cam.fx = cam.fy = 50;
  cam.cx = 0.5 * (width - 1), cam.cy = 0.5 * (height - 1);
  return makeRays(cam);
}

std::multiset<std::size_t> visited(const TileSet& tiles, const SensorRays& rays) {
  std::multiset<std::size_t> out;
  tiles.forEachRay(rays, [&](std::size_t i) { out.insert(i); });
  return out;
}

TEST(TileSet, MixedStridesCastEachRayOnceAndTheFinerSamplingWins) {
  const SensorRays rays = grid(64, 48);
  // A fine region (stride 1) inside a coarse one (stride 4) that covers the whole grid.
  const TileSet tiles = TileSet::sampled(rays, {{{0, 0, 64, 48}, 4}, {{8, 8, 16, 16}, 1}});
  const std::multiset<std::size_t> rays_cast = visited(tiles, rays);
  EXPECT_EQ(rays_cast.size(), tiles.rayCount());
  for (std::size_t i : rays_cast) EXPECT_EQ(rays_cast.count(i), 1u) << "ray " << i;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool fine = x >= 8 && x < 16 && y >= 8 && y < 16;
      const bool coarse = x % 4 == 0 && y % 4 == 0;
      EXPECT_EQ(rays_cast.count(rays.index(x, y)), (fine || coarse) ? 1u : 0u) << x << "," << y;
    }
  EXPECT_EQ(tiles.stride(), 1);  // the finest first
  EXPECT_EQ(tiles.tiles().front().stride, 1);
  EXPECT_EQ(tiles.tiles().back().stride, 4);
}

TEST(TileSet, OneStrideIsTheCoveringOfItsRectangles) {
  const SensorRays rays = grid(64, 48);
  const std::vector<GridRect> rects = {{3, 5, 20, 17}, {40, 30, 64, 48}};
  const TileSet a = TileSet::covering(rays, rects, 2);
  const TileSet b = TileSet::sampled(rays, {{rects[0], 2}, {rects[1], 2}});
  ASSERT_EQ(a.tiles().size(), b.tiles().size());
  EXPECT_EQ(visited(a, rays), visited(b, rays));
}

TEST(TileSet, PhasesShiftTheGridBelowTheStride) {
  const SensorRays rays = grid(64, 48);
  const std::vector<SampledRect> region = {{{0, 0, 64, 48}, 2}};
  const std::multiset<std::size_t> phase0 = visited(TileSet::sampled(rays, region, 0), rays);
  const std::multiset<std::size_t> phase1 = visited(TileSet::sampled(rays, region, 1), rays);
  for (std::size_t i : phase1) EXPECT_EQ(phase0.count(i), 0u) << "phase 1 casts other rays";
  std::set<std::size_t> all;
  for (unsigned phase = 0; phase < 8; ++phase) {
    const TileSet tiles = TileSet::sampled(rays, region, phase);
    const std::multiset<std::size_t> cast = visited(tiles, rays);
    EXPECT_GE(cast.size(), 23u * 31u) << "a quarter of the grid, less a border row or column";
    all.insert(cast.begin(), cast.end());
  }
  EXPECT_EQ(all.size(), rays.size()) << "eight phases reach every ray";
}

}  // namespace
}  // namespace sgt
