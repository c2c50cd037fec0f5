#pragma once
// Per-sample maps over fields: the skeleton of every point-wise operator (Remap, Clamp, Blend, ...).
// The function sees sample values only, so rows run in parallel and the result is independent of the
// thread count.
#include <memory>

#include "graph/heightfield.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

// out = f(a) sample by sample, on a's domain.
template <class F>
std::shared_ptr<Heightfield> map_field(const Heightfield& a, F&& f, const ExecContext* ctx = nullptr) {
  auto out = std::make_shared<Heightfield>(a.domain);
  for_each_row(ctx, a.height(), [&](int j) {
    const auto in = a.row(j);
    auto o = out->row(j);
    for (std::size_t i = 0; i < in.size(); ++i) o[i] = static_cast<float>(f(static_cast<double>(in[i])));
  });
  return out;
}

// out = f(a, b) sample by sample; b must already be on a's domain (see resample_onto).
template <class F>
std::shared_ptr<Heightfield> map_fields(const Heightfield& a, const Heightfield& b, F&& f,
                                        const ExecContext* ctx = nullptr) {
  auto out = std::make_shared<Heightfield>(a.domain);
  for_each_row(ctx, a.height(), [&](int j) {
    const auto ra = a.row(j);
    const auto rb = b.row(j);
    auto o = out->row(j);
    for (std::size_t i = 0; i < ra.size(); ++i)
      o[i] = static_cast<float>(f(static_cast<double>(ra[i]), static_cast<double>(rb[i])));
  });
  return out;
}

// out = f(a, b, c) sample by sample; b and c on a's domain.
template <class F>
std::shared_ptr<Heightfield> map_fields(const Heightfield& a, const Heightfield& b, const Heightfield& c, F&& f,
                                        const ExecContext* ctx = nullptr) {
  auto out = std::make_shared<Heightfield>(a.domain);
  for_each_row(ctx, a.height(), [&](int j) {
    const auto ra = a.row(j);
    const auto rb = b.row(j);
    const auto rc = c.row(j);
    auto o = out->row(j);
    for (std::size_t i = 0; i < ra.size(); ++i)
      o[i] = static_cast<float>(f(static_cast<double>(ra[i]), static_cast<double>(rb[i]), static_cast<double>(rc[i])));
  });
  return out;
}

// A field computed from world positions: out(i, j) = f(x, y) on `domain`.
template <class F>
std::shared_ptr<Heightfield> generate_field(const Domain& domain, F&& f, const ExecContext* ctx = nullptr) {
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) o[static_cast<std::size_t>(i)] = static_cast<float>(f(domain.x(i), y));
  });
  return out;
}

}  // namespace orogen
