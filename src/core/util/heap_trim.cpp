#include "scene_graph_tracker/util/heap_trim.hpp"

#include <atomic>
#include <chrono>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sgt::util {

bool trimHeapEvery(double period_s) {
  using Clock = std::chrono::steady_clock;
  static std::atomic<Clock::rep> last{Clock::now().time_since_epoch().count()};
  const Clock::rep now = Clock::now().time_since_epoch().count();
  Clock::rep before = last.load();
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s));
  if (Clock::duration(now - before) < period) return false;
  if (!last.compare_exchange_strong(before, now)) return false;  // another thread trims
#ifdef __GLIBC__
  malloc_trim(0);
  return true;
#else
  return false;
#endif
}

HeapUsage heapUsage() {
  HeapUsage u;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  u.in_use_mb = static_cast<double>(m.uordblks + m.hblkhd) / 1e6;
  u.free_held_mb = static_cast<double>(m.fordblks) / 1e6;
#endif
  return u;
}

}  // namespace sgt::util
