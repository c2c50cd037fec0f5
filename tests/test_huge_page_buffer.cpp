// HugePageBuffer (nodes/common/huge_page_buffer.h): large arrays start on a 2 MB boundary (the condition for
// the kernel to back them with huge pages), small ones are ordinary memory; every element is usable.
#include <cstdint>
#include <numeric>

#include <gtest/gtest.h>

#include "nodes/common/huge_page_buffer.h"

namespace orogen {
namespace {

TEST(HugePageBuffer, LargeArraysStartOnAHugePageBoundaryAndHoldEveryElement) {
  const std::size_t n = (std::size_t{9} << 20) / sizeof(float) + 3;  // 9 MB and a bit: not a whole number of pages
  HugePageBuffer<float> b(n);
  EXPECT_EQ(b.size(), n);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t{2} << 20), 0u);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<float>(i % 1000);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += b[i];
  double expected = 0.0;
  for (std::size_t i = 0; i < n; ++i) expected += static_cast<double>(i % 1000);
  EXPECT_EQ(sum, expected);
}

TEST(HugePageBuffer, SmallAndEmptyArraysAreOrdinaryMemory) {
  HugePageBuffer<std::uint8_t> small(100);
  EXPECT_NE(small.data(), nullptr);
  std::iota(small.data(), small.data() + 100, std::uint8_t{0});
  EXPECT_EQ(small[99], 99);
  HugePageBuffer<double> empty(0);
  EXPECT_NE(empty.data(), nullptr);
  EXPECT_EQ(empty.size(), 0u);
}

}  // namespace
}  // namespace orogen
