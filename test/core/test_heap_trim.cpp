// util::trimHeapEvery: rate limiting, and that it gives a fragmented heap's free pages back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <vector>

#include "scene_graph_tracker/util/heap_trim.hpp"

namespace {

double residentMb() {
  long pages_total = 0, pages_resident = 0;
  std::ifstream("/proc/self/statm") >> pages_total >> pages_resident;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1e6;
}

}  // namespace

TEST(HeapTrim, TrimsAtMostOncePerPeriod) {
#ifndef __GLIBC__
  GTEST_SKIP() << "malloc_trim is glibc's";
#endif
  EXPECT_TRUE(sgt::util::trimHeapEvery(0.0));
  EXPECT_FALSE(sgt::util::trimHeapEvery(3600.0));  // the last trim was just now
  EXPECT_TRUE(sgt::util::trimHeapEvery(0.0));
}

TEST(HeapTrim, GivesTheFreePagesOfAFragmentedHeapBack) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || !defined(__GLIBC__)
  GTEST_SKIP() << "the sanitizers' allocators are not glibc's arenas";
#endif
  // 1000 blocks of 64 kB (below glibc's mmap threshold, so on the heap), touched; every other one
  // freed: 32 MB of free pages between live blocks, which free() alone keeps resident.
  constexpr std::size_t kBlocks = 1000, kSize = 64 * 1024;
  std::vector<std::unique_ptr<char[]>> blocks;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.emplace_back(new char[kSize]);
    for (std::size_t b = 0; b < kSize; b += 512) blocks.back()[b] = static_cast<char>(i);
  }
  for (std::size_t i = 0; i < kBlocks; i += 2) blocks[i].reset();
  const double before = residentMb();
  ASSERT_TRUE(sgt::util::trimHeapEvery(0.0));
  const double after = residentMb();
  EXPECT_GT(before - after, 24.0) << "resident " << before << " MB before the trim, " << after
                                  << " MB after";
  for (std::size_t i = 1; i < kBlocks; i += 2) EXPECT_EQ(blocks[i][0], static_cast<char>(i));
}

TEST(HeapTrim, ReportsTheBytesInUseAndTheFreeBytesHeld) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || !defined(__GLIBC__)
  GTEST_SKIP() << "the sanitizers' allocators are not glibc's arenas";
#endif
  constexpr std::size_t kBlocks = 400, kSize = 64 * 1024;  // 26 MB on the heap
  const sgt::util::HeapUsage before = sgt::util::heapUsage();
  std::vector<std::unique_ptr<char[]>> blocks;
  for (std::size_t i = 0; i < kBlocks; ++i) blocks.emplace_back(new char[kSize]);
  const sgt::util::HeapUsage held = sgt::util::heapUsage();
  EXPECT_NEAR(held.in_use_mb - before.in_use_mb, kBlocks * kSize / 1e6, 1.0);
  for (std::size_t i = 0; i < kBlocks - 1; i += 2) blocks[i].reset();  // the last one stays
  const sgt::util::HeapUsage freed = sgt::util::heapUsage();
  EXPECT_NEAR(held.in_use_mb - freed.in_use_mb, kBlocks / 2 * kSize / 1e6, 1.0);
  EXPECT_GT(freed.free_held_mb - held.free_held_mb, 0.9 * kBlocks / 2 * kSize / 1e6);
}
