#pragma once
// Cancellation polled by work done, not by iterations of an outer loop: a loop whose single iteration can
// take minutes (a droplet of 1e7 steps, a shadow march of 1e9 cells, a nearest-point search over millions
// of candidates) still stops within a millisecond or so of the cancel.
//
//   WorkPoll poll(ctx);            // ctx may be null: then nothing is checked
//   for (...) { ...; poll(); }     // one unit per inner step (tens of nanoseconds of work)
//   poll(n);                       // or n units at once (n candidates scanned, n samples touched)
//
// Counting is a decrement and a rarely taken branch; every `units_per_check` units (default 4096) the run's
// cancel flag is read (a relaxed atomic load) and Cancelled thrown if it is set. Callers choose the unit so
// that units_per_check of them take well under a millisecond; polling never changes a result. A WorkPoll
// belongs to one thread: parallel loops make one per task.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <utility>

#include "graph/exec_context.h"

namespace orogen {

class WorkPoll {
 public:
  static constexpr std::int64_t kUnitsPerCheck = 4096;

  explicit WorkPoll(const ExecContext* ctx, std::int64_t units_per_check = kUnitsPerCheck)
      : ctx_(ctx), every_(units_per_check > 0 ? units_per_check : 1), left_(every_) {}

  // Counts `units` of work; throws Cancelled once the run is cancelled (checked every units_per_check units).
  void operator()(std::int64_t units = 1) {
    left_ -= units;
    if (left_ <= 0) [[unlikely]]
      check();
  }
  // Checks now and starts a new count.
  void check() {
    left_ = every_;
    if (ctx_) ctx_->check_cancelled();
  }

 private:
  const ExecContext* ctx_;
  std::int64_t every_, left_;
};

// The same for file writers, which reach the run only through their WriteProgress callback (it checks the
// cancel flag, then reports progress; nodes/io/file_error.h): every units_per_check units it is called with
// the fraction of `total` units done, mapped onto [from, to]. A null callback checks nothing.
class ProgressPoll {
 public:
  ProgressPoll(std::function<void(double)> report, double total, double from = 0.0, double to = 1.0,
               std::int64_t units_per_check = WorkPoll::kUnitsPerCheck)
      : report_(std::move(report)),
        total_(total > 0 ? total : 1.0),
        from_(from),
        to_(to),
        every_(units_per_check > 0 ? units_per_check : 1),
        left_(every_) {}

  void operator()(std::int64_t units = 1) {
    done_ += units;
    left_ -= units;
    if (left_ <= 0) [[unlikely]]
      check();
  }
  // Checks (and reports) now and starts a new count.
  void check() {
    left_ = every_;
    if (report_) report_(from_ + (to_ - from_) * std::min(1.0, static_cast<double>(done_) / total_));
  }

 private:
  std::function<void(double)> report_;
  double total_, from_, to_;
  std::int64_t every_, left_, done_ = 0;
};

}  // namespace orogen
