#pragma once
// Counts every heap byte the process holds, for the one test binary that includes this header (it defines the
// C allocation functions, so include it in exactly one translation unit, and never in a build with
// AddressSanitizer, which owns them): malloc, calloc, realloc, free and the aligned variants are interposed and
// forwarded to glibc's (__libc_malloc ...), and each block's usable size is added or subtracted. Everything
// allocates through them: operator new, the huge-page scratch buffers, OpenImageIO, CGAL, TBB's workers. So
// the peak seen between reset_peak() and peak_bytes() is the node's real peak, whatever allocates it.
#include <malloc.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

namespace orogen::test::counting_malloc {

inline constinit std::atomic<std::int64_t> g_current{0};
inline constinit std::atomic<std::int64_t> g_peak{0};

inline void add(void* p) {
  if (!p) return;
  const auto n = static_cast<std::int64_t>(malloc_usable_size(p));
  const std::int64_t now = g_current.fetch_add(n, std::memory_order_relaxed) + n;
  std::int64_t peak = g_peak.load(std::memory_order_relaxed);
  while (now > peak && !g_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {}
}
inline void remove(void* p) {
  if (p) g_current.fetch_sub(static_cast<std::int64_t>(malloc_usable_size(p)), std::memory_order_relaxed);
}

// Bytes held now; the peak since the last reset_peak().
inline std::int64_t current_bytes() { return g_current.load(); }
inline std::int64_t peak_bytes() { return g_peak.load(); }
inline void reset_peak() { g_peak.store(g_current.load()); }

}  // namespace orogen::test::counting_malloc

extern "C" {
void* malloc(std::size_t n) {
  void* p = __libc_malloc(n);
  orogen::test::counting_malloc::add(p);
  return p;
}
void* calloc(std::size_t n, std::size_t size) {
  void* p = __libc_calloc(n, size);
  orogen::test::counting_malloc::add(p);
  return p;
}
void* realloc(void* old, std::size_t n) {
  orogen::test::counting_malloc::remove(old);
  void* p = __libc_realloc(old, n);
  if (p)
    orogen::test::counting_malloc::add(p);
  else if (n != 0)
    orogen::test::counting_malloc::add(old);  // failed: the old block stays
  return p;
}
void free(void* p) {
  orogen::test::counting_malloc::remove(p);
  __libc_free(p);
}
void* memalign(std::size_t alignment, std::size_t n) {
  void* p = __libc_memalign(alignment, n);
  orogen::test::counting_malloc::add(p);
  return p;
}
void* aligned_alloc(std::size_t alignment, std::size_t n) { return memalign(alignment, n); }
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  void* p = memalign(alignment, n);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(std::size_t n) { return memalign(4096, n); }
}
