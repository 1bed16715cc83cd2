// Giving freed heap memory back to the operating system.
//
// glibc keeps the pages of freed blocks inside its arenas for reuse. A process whose live heap is
// flat but bursty (a queue of 1 MB images that fills when processing falls behind, per-frame
// buffers) then keeps the high-water mark of every burst as resident memory, and its RSS climbs in
// steps over many minutes. malloc_trim() releases the whole free pages of every arena.
#pragma once

namespace sgt::util {

// Calls malloc_trim(0) when at least `period_s` seconds (steady clock) have passed since this
// process last did; otherwise does nothing. Thread-safe; one trim at a time. A no-op without glibc.
// Returns whether it trimmed.
bool trimHeapEvery(double period_s);

// What the allocator holds now (glibc's mallinfo2, over all arenas): bytes in blocks the program
// uses, and bytes in the free blocks it keeps for reuse (a trim gives their whole pages back to
// the system but keeps the blocks, so this is an upper bound of the free memory resident). Both 0
// without glibc.
struct HeapUsage {
  double in_use_mb = 0.0;
  double free_held_mb = 0.0;
};
HeapUsage heapUsage();

}  // namespace sgt::util
