#pragma once
// Benchmarks of routines that return their results in new large vectors: glibc serves such blocks from mmap
// and unmaps them on free, so every iteration would page-fault hundreds of MB in again (first-touch page
// faults, not the algorithm). Keeping freed memory in the heap makes the timed calls reuse touched pages,
// as the buffers of a long-running evaluation are. (M_MMAP_THRESHOLD cannot do this: glibc refuses
// thresholds above 32 MB.)
#include <climits>

#include <malloc.h>

namespace orogen::bench {

inline void keep_freed_memory_in_heap() {
  mallopt(M_MMAP_MAX, 0);              // no block from mmap: all from the heap
  mallopt(M_TRIM_THRESHOLD, INT_MAX);  // and never give the heap's top back
}

}  // namespace orogen::bench
