// Pairs gathered in parallel over the tiles of a ray set, kept in tile order whatever the thread
// scheduling: the alignment's float sums over them then do not depend on it either, and a run
// over a bag repeats exactly (it did not while threads appended to their own lists: the order of
// the pairs changed the sums in the last bits, and the tracker's decisions amplified that into
// runs whose recall differed by 0.02).
#pragma once

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "scene_graph_tracker/registration/ray_correspondences.hpp"

namespace sgt {

// Calls visit(tile, pairs_by_group, counts_by_group) for every tile index in [0, n_tiles), in
// parallel over chunks of tiles, and appends the pairs to out[group] (and the counts to
// *counts[group]) chunk by chunk in tile order. counts may be null (visit then gets null).
template <typename Visit>
void collectInTileOrder(std::size_t n_tiles, std::vector<std::vector<RayPair>>& out,
                        std::vector<int>* counts, Visit&& visit) {
  constexpr std::size_t kChunk = 32;  // tiles of 16 rays
  const std::size_t n_groups = out.size(), n_chunks = (n_tiles + kChunk - 1) / kChunk;
  std::vector<std::vector<std::vector<RayPair>>> pairs(n_chunks,
                                                       std::vector<std::vector<RayPair>>(n_groups));
  std::vector<std::vector<int>> chunk_counts(counts ? n_chunks : 0, std::vector<int>(n_groups, 0));
  tbb::parallel_for(std::size_t{0}, n_chunks, [&](std::size_t c) {
    int* count = counts ? chunk_counts[c].data() : nullptr;
    for (std::size_t b = c * kChunk; b < std::min(n_tiles, (c + 1) * kChunk); ++b)
      visit(b, pairs[c], count);
  });
  for (std::size_t c = 0; c < n_chunks; ++c)
    for (std::size_t g = 0; g < n_groups; ++g) {
      out[g].insert(out[g].end(), pairs[c][g].begin(), pairs[c][g].end());
      if (counts) (*counts)[g] += chunk_counts[c][g];
    }
}

}  // namespace sgt
