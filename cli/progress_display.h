#pragma once
// Live per-node progress on a terminal: finished nodes are printed as permanent lines, running nodes share
// one status line redrawn in place at most ten times a second. Fed from evaluator worker threads.
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>

#include "evaluator/evaluator.h"

namespace orogen::cli {

class ProgressDisplay {
 public:
  explicit ProgressDisplay(std::FILE* out, std::size_t node_count) : out_(out), total_(node_count) {}
  void on_event(const EvalEvent& e);
  void finish();  // clears the status line

 private:
  void redraw_locked(bool force);
  void print_line_locked(const std::string& line);

  std::FILE* out_;
  std::size_t total_;
  std::size_t done_ = 0;
  std::mutex mutex_;
  std::map<std::string, double> running_;  // node id -> fraction
  std::chrono::steady_clock::time_point last_draw_{};
  bool status_shown_ = false;
};

}  // namespace orogen::cli
