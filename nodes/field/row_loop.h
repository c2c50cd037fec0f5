#pragma once
// Row loops for field algorithms. Inside a node the loop goes through parallel_rows (cancellation and
// progress); called as a plain library function (no context) it is a bare tbb::parallel_for. Either way
// every row is computed by exactly one call from its inputs only, so results do not depend on the thread
// count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/common/parallel_rows.h"

namespace orogen {

template <class Fn>
void for_each_row(const ExecContext* ctx, int count, Fn&& fn, double progress_from = 0.0, double progress_to = 1.0) {
  if (ctx) {
    parallel_rows(*ctx, count, fn, progress_from, progress_to);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 8), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) fn(j);
  });
}

}  // namespace orogen
