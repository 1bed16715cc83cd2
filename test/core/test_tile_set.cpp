// TileSet: regions sampled at their own strides (each ray cast once, the finer sampling wins where
// they overlap) and phases that shift a sampled grid so that successive casts see other rays; the
// sampling of the rays near an object bounded by the rays that reach it.
#include <gtest/gtest.h>

#include <set>

#include "scene_graph_tracker/registration/ray_regions.hpp"
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

// A 20 cm box 0.6 m in front of a VGA camera fills a region of tens of thousands of pixels. The
// bound counts that region's rays until the rays that reach the object are known; then those: an
// object that shows 200 rays keeps its stride, one that shows 5,000 (at stride 2: 20,000 cells) is
// sampled at 9, the smallest stride at which it shows at most 300 (20,000 / 81 = 247), not at the
// next power of two (16: 78 rays).
TEST(SampleRaysNearObjects, TheBoundCountsTheRaysThatReachTheObjectWhereKnown) {
  const PinholeModel cam = PinholeModel::xtion();
  const auto rays = std::make_shared<SensorRays>(makeRays(cam));
  const RangeMeasurements m = fromDepthImage(cam, rays, std::vector<float>(rays->size(), 1.0f),
                                             Eigen::Isometry3d::Identity());
  ObjectExtent box{
      Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.6)),
      Eigen::AlignedBox3f(Eigen::Vector3f::Constant(-0.1f), Eigen::Vector3f::Constant(0.1f))};
  const auto strideFor = [&](double on_object) {
    const std::vector<double> seen = {on_object};
    RaySampling request;
    request.stride = 2, request.max_rays = 300, request.on_object = &seen;
    const ObjectSampling s = sampleRaysNearObjects(m, {box}, request);
    EXPECT_EQ(s.weight.at(0), (s.regions.at(0).stride / 2.0f) * (s.regions.at(0).stride / 2.0f));
    return s.regions.at(0).stride;
  };
  const GridRect r = raysNearObjects(m, {box}, 0.0f).at(0);
  const double region = static_cast<double>(r.x1 - r.x0) * (r.y1 - r.y0) / 4.0;
  ASSERT_GT(region, 16 * 300) << "the region's rays at stride 2";
  EXPECT_GE(strideFor(-1.0), 8) << "unknown: the region's rays are bounded";
  EXPECT_EQ(strideFor(200.0), 2);
  EXPECT_EQ(strideFor(5000.0), 9);
  EXPECT_EQ(strideFor(4800.0), 8) << "at the bound: 19,200 / 64 = 300";
  RaySampling unbounded;
  unbounded.stride = 2;
  EXPECT_EQ(sampleRaysNearObjects(m, {box}, unbounded).regions.at(0).stride, 2) << "no bound";
}

}  // namespace
}  // namespace sgt
