#pragma once
// Data-parallel loops for node algorithms: rows (or any index range) split across the oneTBB arena the
// evaluator runs in, with cancellation checked between chunks and progress reported as rows complete.
// Each index is processed by exactly one call, and the result of a row must depend on that row only, so
// the output is bit-identical for any thread count.
#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/exec_context.h"

namespace orogen {

// Calls fn(j) for j in [0, count). Progress covers [progress_from, progress_to] of the node's total.
template <class Fn>
void parallel_rows(const ExecContext& ctx, int count, Fn&& fn, double progress_from = 0.0, double progress_to = 1.0) {
  std::atomic<int> done{0};
  const int report_every = std::max(1, count / 100);
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 8), [&](const tbb::blocked_range<int>& r) {
    ctx.check_cancelled();
    for (int j = r.begin(); j != r.end(); ++j) fn(j);
    const int before = done.fetch_add(static_cast<int>(r.size()));
    if ((before + static_cast<int>(r.size())) / report_every != before / report_every)
      ctx.progress(progress_from + (progress_to - progress_from) * (before + static_cast<double>(r.size())) / count);
  });
  ctx.check_cancelled();
}

}  // namespace orogen
