// Which rays of a sensor's ray grid a cast covers: coherent tiles of 4 x 4 rays (16 x 1 on grids of
// fewer than 4 rows), each sampling the grid at a stride. A region sampled at stride s casts every
// s-th ray in x and y; its tiles span 4s x 4s grid cells, aligned to multiples of 4s.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <bitset>
#include <cstdint>
#include <vector>

#include "scene_graph_tracker/sensors/sensor_models.hpp"

namespace sgt {

// Rectangle of a ray grid: columns [x0, x1), rows [y0, y1).
struct GridRect {
  int x0, y0, x1, y1;
};

// A rectangle of the grid and the stride to sample it at.
struct SampledRect {
  GridRect rect;
  int stride = 1;
};

class TileSet {
 public:
  struct Tile {
    std::int32_t x0, y0;   // grid cell of lane 0
    std::uint16_t stride;  // grid cells between neighbouring lanes
    std::uint16_t lanes;   // bit k set: lane k is cast
  };

  TileSet() = default;
  static TileSet all(const SensorRays& rays);
  // Tiles over the union of `rects`, every `stride`-th ray in x and y.
  static TileSet covering(const SensorRays& rays, const std::vector<GridRect>& rects,
                          int stride = 1);
  // Tiles over the union of `regions`, each at its own stride. A ray is cast once: where regions
  // of different strides overlap, a coarser tile drops the lanes a finer one casts too (the
  // finer sampling wins). Tiles come by stride, finest first, then row by row. `phase` > 0 shifts
  // each stride's grid by an offset below the stride (a low-discrepancy sequence over phases), so
  // that successive casts at phases 0, 1, 2... sample different rays.
  static TileSet sampled(const SensorRays& rays, const std::vector<SampledRect>& regions,
                         unsigned phase = 0);

  int stride() const { return tiles_.empty() ? 1 : tiles_.front().stride; }  // the finest
  const std::vector<Tile>& tiles() const { return tiles_; }
  std::size_t rayCount() const { return rays_; }
  // Calls f(lane, ray_index) for the cast rays of tile `b` (index into tiles()); lane 0..15.
  template <typename F>
  void forTile(const SensorRays& rays, std::size_t b, F&& f) const;
  // Keeps only the rays for which keep(ray_index) holds; tiles left without a ray go.
  template <typename Keep>
  void keepRays(const SensorRays& rays, Keep&& keep);
  // Keeps of each tile only the lanes set in lanes(tile) (a mask, bit k: lane k); tiles left
  // without a lane go.
  template <typename Lanes>
  void keepLanes(Lanes&& lanes);
  // Calls f(ray_index) for every ray of the covered tiles.
  template <typename F>
  void forEachRay(const SensorRays& rays, F&& f) const {
    for (std::size_t b = 0; b < tiles_.size(); ++b)
      forTile(rays, b, [&](int, std::size_t i) { f(i); });
  }

 private:
  int tile_w_ = 4, tile_h_ = 4;
  std::size_t rays_ = 0;
  std::vector<Tile> tiles_;
};

template <typename F>
void TileSet::forTile(const SensorRays& rays, std::size_t b, F&& f) const {
  const Tile& t = tiles_[b];
  for (int k = 0; k < tile_w_ * tile_h_; ++k) {
    if (!((t.lanes >> k) & 1u)) continue;
    const int x = t.x0 + (k % tile_w_) * t.stride, y = t.y0 + (k / tile_w_) * t.stride;
    f(k, static_cast<std::size_t>(y) * rays.width + x);
  }
}

template <typename Keep>
void TileSet::keepRays(const SensorRays& rays, Keep&& keep) {
  keepLanes([&](const Tile& t) {
    std::uint16_t kept = 0;
    forTile(rays, static_cast<std::size_t>(&t - tiles_.data()), [&](int k, std::size_t i) {
      if (keep(i)) kept |= static_cast<std::uint16_t>(1u << k);
    });
    return kept;
  });
}

template <typename Lanes>
void TileSet::keepLanes(Lanes&& lanes_of) {
  std::vector<std::uint16_t> lanes(tiles_.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles_.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t b = r.begin(); b != r.end(); ++b)
                        lanes[b] =
                            static_cast<std::uint16_t>(tiles_[b].lanes & lanes_of(tiles_[b]));
                    });
  std::size_t kept_tiles = 0;
  rays_ = 0;
  for (std::size_t b = 0; b < tiles_.size(); ++b) {
    if (lanes[b] == 0) continue;
    tiles_[kept_tiles] = tiles_[b];
    tiles_[kept_tiles++].lanes = lanes[b];
    rays_ += std::bitset<16>(lanes[b]).count();
  }
  tiles_.resize(kept_tiles);
}

}  // namespace sgt
