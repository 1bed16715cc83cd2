#include "scene_graph_tracker/scene/tile_set.hpp"

#include <algorithm>
#include <bitset>

namespace sgt {
namespace {

// The tiles of one stride: which of the grid's 4s x 4s tiles any region of that stride touches.
struct StrideLevel {
  int stride, span_w, span_h, tiles_x, tiles_y, ox, oy;
  std::vector<char> used;

  bool casts(int x, int y) const {  // this level casts grid cell (x, y)
    x -= ox, y -= oy;
    return x >= 0 && y >= 0 && x % stride == 0 && y % stride == 0 &&
           used[static_cast<std::size_t>(y / span_h) * tiles_x + x / span_w];
  }
};

// The radical inverse of i in `base`: a sequence that fills [0, 1) evenly.
double radicalInverse(unsigned i, unsigned base) {
  double f = 1.0, r = 0.0;
  for (; i > 0; i /= base) f /= base, r += f * (i % base);
  return r;
}

StrideLevel levelOf(const SensorRays& rays, int tile_w, int tile_h, int stride,
                    const std::vector<SampledRect>& regions, unsigned phase) {
  StrideLevel l{stride, tile_w * stride, tile_h * stride, 0, 0, 0, 0, {}};
  if (phase > 0 && stride > 1) {
    l.ox = static_cast<int>(radicalInverse(phase, 2) * stride);
    l.oy = static_cast<int>(radicalInverse(phase, 3) * stride);
  }
  l.tiles_x = (rays.width - l.ox + l.span_w - 1) / l.span_w;
  l.tiles_y = (rays.height - l.oy + l.span_h - 1) / l.span_h;
  l.used.assign(static_cast<std::size_t>(l.tiles_x) * l.tiles_y, 0);
  for (const SampledRect& region : regions) {
    if (std::max(1, region.stride) != stride) continue;
    const GridRect& r = region.rect;
    const int x0 = std::max(0, r.x0 - l.ox), y0 = std::max(0, r.y0 - l.oy);
    const int x1 = std::min(rays.width, r.x1) - l.ox, y1 = std::min(rays.height, r.y1) - l.oy;
    if (x0 >= x1 || y0 >= y1) continue;
    for (int ty = y0 / l.span_h; ty <= (y1 - 1) / l.span_h; ++ty)
      for (int tx = x0 / l.span_w; tx <= (x1 - 1) / l.span_w; ++tx)
        l.used[static_cast<std::size_t>(ty) * l.tiles_x + tx] = 1;
  }
  return l;
}

}  // namespace

TileSet TileSet::all(const SensorRays& rays) {
  return covering(rays, {GridRect{0, 0, rays.width, rays.height}}, 1);
}

TileSet TileSet::covering(const SensorRays& rays, const std::vector<GridRect>& rects, int stride) {
  std::vector<SampledRect> regions;
  regions.reserve(rects.size());
  for (const GridRect& r : rects) regions.push_back({r, stride});
  return sampled(rays, regions);
}

TileSet TileSet::sampled(const SensorRays& rays, const std::vector<SampledRect>& regions,
                         unsigned phase) {
  TileSet set;
  if (rays.height < 4) set.tile_w_ = 16, set.tile_h_ = 1;
  std::vector<int> strides;
  for (const SampledRect& r : regions) strides.push_back(std::max(1, r.stride));
  std::sort(strides.begin(), strides.end());
  strides.erase(std::unique(strides.begin(), strides.end()), strides.end());
  std::vector<StrideLevel> levels;
  for (const int s : strides)
    levels.push_back(levelOf(rays, set.tile_w_, set.tile_h_, s, regions, phase));
  for (std::size_t li = 0; li < levels.size(); ++li) {
    const StrideLevel& l = levels[li];
    for (std::size_t t = 0; t < l.used.size(); ++t) {
      if (!l.used[t]) continue;
      Tile tile{static_cast<std::int32_t>(l.ox + (t % l.tiles_x) * l.span_w),
                static_cast<std::int32_t>(l.oy + (t / l.tiles_x) * l.span_h),
                static_cast<std::uint16_t>(l.stride), 0};
      const bool inside = tile.x0 + (set.tile_w_ - 1) * l.stride < rays.width &&
                          tile.y0 + (set.tile_h_ - 1) * l.stride < rays.height;
      if (li == 0 && inside) {  // the common case: every lane, nothing to check
        tile.lanes = static_cast<std::uint16_t>((1u << (set.tile_w_ * set.tile_h_)) - 1u);
      } else {
        for (int k = 0; k < set.tile_w_ * set.tile_h_; ++k) {
          const int x = tile.x0 + (k % set.tile_w_) * l.stride;
          const int y = tile.y0 + (k / set.tile_w_) * l.stride;
          if (x >= rays.width || y >= rays.height) continue;
          const bool finer = std::any_of(levels.begin(), levels.begin() + li,
                                         [&](const StrideLevel& f) { return f.casts(x, y); });
          if (!finer) tile.lanes |= static_cast<std::uint16_t>(1u << k);
        }
      }
      if (tile.lanes == 0) continue;
      set.rays_ += std::bitset<16>(tile.lanes).count();
      set.tiles_.push_back(tile);
    }
  }
  return set;
}

}  // namespace sgt
