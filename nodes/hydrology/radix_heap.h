#pragma once
// A monotone priority queue of 64-bit keys: the binary radix heap of Ahuja, Mehlhorn, Orlin and Tarjan (1990, "Faster
// algorithms for the shortest path problem", J. ACM 37). It serves a flood whose keys never fall below the last one
// taken, and pops them in exactly the order a binary heap would, ties included (the tile flood's labels depend on it,
// nodes/hydrology/tile_fill.cpp), at a fraction of its cost: a key waits in the bucket of the highest bit where it
// differs from the last key taken and moves to a lower bucket only when its bucket is emptied, a few times in all,
// where a binary heap's pop sifts through log2(size) levels of scattered memory. (The whole-domain fill's heap in
// nodes/hydrology/flow_routing.cpp has radix 256 and lets equal heights leave in any fixed order, which that fill
// allows and this flood's labels do not.)
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace orogen::hydrology {

class RadixHeap {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  // Throws std::logic_error for a key below the last one popped: the order would no longer be a heap's.
  void push(std::uint64_t key) {
    if (key < last_) throw std::logic_error("RadixHeap: a key below the last one taken");
    const int b = bucket(key);
    buckets_[static_cast<std::size_t>(b)].push_back(key);
    if (b > 0) filled_ |= std::uint64_t{1} << (b - 1);
    ++size_;
  }

  // The least key, removed. The heap must not be empty.
  std::uint64_t pop() {
    if (buckets_[0].empty()) {
      // The lowest filled bucket holds the least key; its keys share their bits above the bucket's with it, so
      // measured from it they all fall into lower buckets.
      const int b = std::countr_zero(filled_) + 1;
      auto& from = buckets_[static_cast<std::size_t>(b)];
      std::uint64_t least = from.front();
      for (const std::uint64_t k : from) least = k < least ? k : least;
      last_ = least;
      filled_ &= ~(std::uint64_t{1} << (b - 1));
      for (const std::uint64_t k : from) {
        const int to = bucket(k);
        buckets_[static_cast<std::size_t>(to)].push_back(k);
        if (to > 0) filled_ |= std::uint64_t{1} << (to - 1);
      }
      from.clear();
    }
    const std::uint64_t key = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return key;
  }

 private:
  // 0 for the last key taken, else 1 + the index of the highest bit where `key` differs from it.
  int bucket(std::uint64_t key) const { return key == last_ ? 0 : 64 - std::countl_zero(key ^ last_); }

  std::array<std::vector<std::uint64_t>, 65> buckets_;
  std::uint64_t filled_ = 0;  // bit b - 1 set: bucket b (1 to 64) holds keys
  std::uint64_t last_ = 0;    // the last key popped
  std::size_t size_ = 0;
};

}  // namespace orogen::hydrology
