#pragma once
// Checked work counts. Step, sub-step and iteration counts derived from parameters (duration / time step,
// length / step length ...) are computed here, never by a bare cast of a double to an int (undefined
// behaviour when it does not fit, and a silently wrong simulation), and a node's planned work is held to a
// declared ceiling. Either failure is a NodeError, raised before the work starts, that names the parameters
// to change.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

#include "graph/exec_context.h"

namespace orogen {

// The most work one node may plan, in elementary updates (one sample of one step, one march step of one
// ray, one droplet step ...): about an hour of one core. Plans beyond it are refused up front.
inline constexpr double kMaxNodeWork = 1e13;

namespace detail {
inline std::string work_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}
}  // namespace detail

// ceil(value) as a count in [1, max_count] (0 stays 0 when allow_zero). `what` says what is counted and from
// which parameters ("time steps (duration / time_step)"), `change` what to do ("raise time_step or lower
// duration"). A non-finite value or one above max_count is a NodeError; a negative one counts as 0.
inline std::int64_t checked_count(double value, std::string_view what, std::string_view change,
                                  std::int64_t max_count = std::numeric_limits<std::int32_t>::max(),
                                  bool allow_zero = false) {
  const double c = std::ceil(value);
  if (!(c <= static_cast<double>(max_count)))  // also NaN and +inf
    throw NodeError(std::string(what) + ": " + (std::isnan(c) ? std::string("not a number") : detail::work_number(c)) +
                    " exceeds the limit of " + detail::work_number(static_cast<double>(max_count)) + "; " +
                    std::string(change));
  if (!(c >= 1.0)) return allow_zero ? 0 : 1;
  return static_cast<std::int64_t>(c);
}

// Refuses a plan of `units` elementary updates above kMaxNodeWork (or non-finite).
inline void check_work(double units, std::string_view what, std::string_view change) {
  if (!(units <= kMaxNodeWork))
    throw NodeError(std::string(what) + ": " +
                    (std::isnan(units) ? std::string("not a number") : detail::work_number(units)) +
                    " updates planned, above the per-node ceiling of " + detail::work_number(kMaxNodeWork) + "; " +
                    std::string(change));
}

}  // namespace orogen
