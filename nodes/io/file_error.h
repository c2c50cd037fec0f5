#pragma once
// A file could not be read or written: missing, unreadable, unsupported, or the data cannot be stored in
// the format. The message names the file and says what went wrong; nodes pass it on as a NodeError.
#include <functional>
#include <stdexcept>

namespace orogen {

struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Called by the file writers after each row (or block of items) with the fraction done. It may throw to
// abort the write (the evaluator's cancellation does), in which case the writer stops at once.
using WriteProgress = std::function<void(double fraction)>;

}  // namespace orogen
