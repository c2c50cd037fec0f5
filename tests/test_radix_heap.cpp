#include "nodes/hydrology/radix_heap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <queue>
#include <random>
#include <vector>

namespace orogen::hydrology {
namespace {

// A flood's pattern: pops interleaved with pushes at or above the last key popped, keys spread over all 64 bits and
// close together (equal levels, neighbouring cells), duplicates included. The radix heap pops what a binary heap pops.
TEST(RadixHeap, PopsInTheBinaryHeapsOrderForMonotoneKeys) {
  std::mt19937_64 random(7);
  RadixHeap heap;
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<>> reference;
  const auto push = [&](std::uint64_t key) { heap.push(key), reference.push(key); };
  for (int k = 0; k < 1000; ++k) push(random() >> (random() % 64));
  std::uint64_t last = 0;
  std::size_t popped = 0;
  while (!reference.empty()) {
    ASSERT_EQ(heap.size(), reference.size());
    const std::uint64_t key = heap.pop();
    ASSERT_EQ(key, reference.top());
    reference.pop();
    ASSERT_GE(key, last);
    last = key;
    ++popped;
    if (popped < 20000)
      for (int k = static_cast<int>(random() % 3); k > 0; --k) {
        const std::uint64_t step = random() % 4 == 0 ? 0 : random() >> (random() % 64);
        push(last + std::min(step, ~std::uint64_t{0} - last));
      }
  }
  EXPECT_TRUE(heap.empty());
  EXPECT_GT(popped, 5000u);
}

TEST(RadixHeap, RefusesAKeyBelowTheLastOnePopped) {
  RadixHeap heap;
  heap.push(10), heap.push(30);
  EXPECT_EQ(heap.pop(), 10u);
  EXPECT_THROW(heap.push(9), std::logic_error);
  heap.push(10);  // equal to the last one popped: still in order
  EXPECT_EQ(heap.pop(), 10u);
  EXPECT_EQ(heap.pop(), 30u);
  EXPECT_TRUE(heap.empty());
}

}  // namespace
}  // namespace orogen::hydrology
