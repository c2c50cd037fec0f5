#pragma once
// Cooperative cancellation: set from any thread, polled by long loops through ExecContext.
#include <atomic>
#include <exception>

namespace orogen {

class CancelToken {
 public:
  void cancel() { flag_.store(true, std::memory_order_relaxed); }
  void reset() { flag_.store(false, std::memory_order_relaxed); }
  bool cancelled() const { return flag_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> flag_{false};
};

// Thrown by ExecContext::check_cancelled; the evaluator treats it as "cancelled", never as an error.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

}  // namespace orogen
