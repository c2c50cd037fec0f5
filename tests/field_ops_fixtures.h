#pragma once
// Helpers shared by the field-operator tests (test_field_ops*.cpp): analytic input fields, running a node
// with a given thread count, and comparing fields.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <vector>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include <tbb/task_arena.h>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "nodes/common/hash.h"

namespace orogen::test {

// A field sampled from a function of the world position.
template <class F>
HeightfieldPtr field_from(const Domain& d, F&& f) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(f(d.x(i), d.y(j)));
  return h;
}

// Smooth, non-trivial terrain-like heights in metres (a few hundred metres of relief over kilometres).
inline double rolling_hills(double x, double y) {
  return 220.0 * std::sin(x / 310.0) * std::cos(y / 270.0) + 90.0 * std::sin((x + 2.0 * y) / 530.0) + 0.05 * x + 40.0;
}

// Deterministic pseudo-random value in [0, 1) per integer pair (splitmix64 of the pair).
inline double hash01(std::int64_t a, std::int64_t b) {
  return unit_double(
      mix64(static_cast<std::uint64_t>(a) * kGoldenGamma + static_cast<std::uint64_t>(b) + 0x632BE59BD9B4E019ull));
}

// Runs `fn` inside an arena of `threads` worker slots, so the node sees exactly that parallelism.
template <class Fn>
auto with_threads(int threads, Fn&& fn) {
  tbb::task_arena arena(threads);
  return arena.execute(fn);
}

// A thread count above one that the machine can honour (2..4).
inline int several_threads() { return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 2u, 4u)); }

inline HeightfieldPtr run_field(const std::string& type, const Domain& d,
                                const std::map<std::string, ParamValue>& params = {},
                                const std::map<std::string, PortValue>& inputs = {}, std::size_t output = 0) {
  return run_node(type, d, params, inputs).get<Heightfield>(output);
}

// Bitwise equality of two fields (NaNs compare by bits too).
inline bool bit_identical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                            [](float x, float y) { return std::memcmp(&x, &y, sizeof(float)) == 0; });
}

// Pearson correlation of two equally long sample sets.
inline double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sab += (a[k] - ma) * (b[k] - mb);
    saa += (a[k] - ma) * (a[k] - ma);
    sbb += (b[k] - mb) * (b[k] - mb);
  }
  if (saa == 0 && sbb == 0) return 1.0;
  return sab / std::sqrt(saa * sbb);
}

}  // namespace orogen::test
