#include "nodes/common/huge_page_buffer.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace orogen::huge_pages {
namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kMinBytes = std::size_t{8} << 20;  // below this, alignment waste outweighs TLB reach
}  // namespace

void* allocate(std::size_t bytes) {
  void* p = nullptr;
  if (bytes >= kMinBytes) {
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    p = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Only a hint: where it is refused the memory is simply in small pages.
    if (p) madvise(p, rounded, MADV_HUGEPAGE);
#endif
  } else {
    p = std::malloc(bytes > 0 ? bytes : 1);
  }
  if (!p) throw std::bad_alloc();
  return p;
}

void release(void* p) { std::free(p); }

}  // namespace orogen::huge_pages
