#pragma once
// A fixed-size scratch array for large grids that an algorithm visits in scattered order (priority queues,
// breadth-first fronts): on Linux it asks for 2 MB transparent huge pages, so one TLB entry covers 512 times
// as much memory. With 4 KB pages a 4096^2 float grid spans 16,384 pages, and a flood that jumps between
// rows misses the TLB on almost every cell (Priority-Flood on 4096^2 fBm: 1.2x faster with huge pages).
// Small arrays, other systems and kernels without transparent huge pages get ordinary memory.
// The elements are not initialised: the owner writes every element before it reads it.
#include <cstddef>
#include <type_traits>
#include <vector>

namespace orogen {

namespace huge_pages {
// Memory for `bytes` bytes (0 allowed): from 8 MB up 2 MB aligned and advised for huge pages. Throws
// std::bad_alloc when there is none.
void* allocate(std::size_t bytes);
void release(void* p);
// Asks for huge pages under the whole 2 MB pages of [p, p + bytes), before anything touches them (a hint, for
// memory owned elsewhere, e.g. a large std::vector's reserved buffer): a 64 MB grid then takes 32 first-touch
// faults instead of 16,384, which on this VM cost more CPU than filling it. Below kMinBytes it does nothing.
void advise(void* p, std::size_t bytes);

// An empty vector given n value-initialised elements, or a copy of `from`, in huge pages where advise gives
// them (large grids a node returns: the same values as resize / assignment).
template <class T>
void resize_fresh(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise(v.data(), v.capacity() * sizeof(T));
  v.resize(n);
}
template <class T>
void assign_fresh(std::vector<T>& v, const std::vector<T>& from) {
  v.reserve(from.size());
  advise(v.data(), v.capacity() * sizeof(T));
  v.assign(from.begin(), from.end());
}
}  // namespace huge_pages

template <class T>
class HugePageBuffer {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  explicit HugePageBuffer(std::size_t n) : data_(static_cast<T*>(huge_pages::allocate(n * sizeof(T)))), size_(n) {}
  ~HugePageBuffer() { huge_pages::release(data_); }
  HugePageBuffer(const HugePageBuffer&) = delete;
  HugePageBuffer& operator=(const HugePageBuffer&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  T* data_;
  std::size_t size_;
};

}  // namespace orogen
