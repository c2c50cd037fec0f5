#pragma once
// Data-parallel row loops for node algorithms: rows (or any index range) split across the oneTBB arena the
// evaluator runs in, with cancellation checked between chunks and progress reported as rows complete.
// Each index is processed by exactly one call, and the result of a row must depend on that row only, so
// the output is bit-identical for any thread count. Every parallel row loop of the nodes goes through here:
// a bare tbb::parallel_for would not stop when the run is cancelled.
#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/exec_context.h"

namespace orogen {
namespace detail {

// Rows per task: small enough to balance, large enough that the cancellation check costs nothing.
inline constexpr int kRowGrain = 8;

template <class Fn>
void run_rows(const ExecContext* ctx, int count, Fn& fn, bool report, double progress_from, double progress_to) {
  std::atomic<int> done{0};
  const int report_every = std::max(1, count / 100);
  tbb::parallel_for(tbb::blocked_range<int>(0, count, kRowGrain), [&](const tbb::blocked_range<int>& r) {
    if (ctx) ctx->check_cancelled();
    for (int j = r.begin(); j != r.end(); ++j) fn(j);
    if (!ctx || !report) return;
    const int before = done.fetch_add(static_cast<int>(r.size()));
    if ((before + static_cast<int>(r.size())) / report_every != before / report_every)
      ctx->progress(progress_from + (progress_to - progress_from) * (before + static_cast<double>(r.size())) / count);
  });
  if (ctx) ctx->check_cancelled();
}

}  // namespace detail

// Calls fn(j) for j in [0, count). Progress covers [progress_from, progress_to] of the node's total.
template <class Fn>
void parallel_rows(const ExecContext& ctx, int count, Fn&& fn, double progress_from = 0.0, double progress_to = 1.0) {
  detail::run_rows(&ctx, count, fn, true, progress_from, progress_to);
}

// The same for algorithms whose context is optional: without one (a plain library call) nothing is checked
// or reported.
template <class Fn>
void for_each_row(const ExecContext* ctx, int count, Fn&& fn, double progress_from = 0.0, double progress_to = 1.0) {
  detail::run_rows(ctx, count, fn, true, progress_from, progress_to);
}

// A row loop inside an iteration that reports progress itself (a simulation's time step): cancellation only.
template <class Fn>
void for_each_row_unreported(const ExecContext* ctx, int count, Fn&& fn) {
  detail::run_rows(ctx, count, fn, false, 0.0, 0.0);
}

}  // namespace orogen
