#include "cli/progress_display.h"

#include <cstdio>

namespace orogen::cli {

void ProgressDisplay::print_line_locked(const std::string& line) {
  if (status_shown_) std::fputs("\r\033[K", out_);
  std::fputs(line.c_str(), out_);
  std::fputc('\n', out_);
  status_shown_ = false;
}

void ProgressDisplay::redraw_locked(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  char head[48];
  std::snprintf(head, sizeof head, "[%zu/%zu]", done_, total_);
  std::string line = head;
  for (const auto& [id, fraction] : running_) {
    const int pct = static_cast<int>(fraction * 100.0 + 0.5);
    line += " " + id + " " + std::to_string(pct) + "%";
    if (line.size() > 110) {
      line += " ...";
      break;
    }
  }
  std::fputs("\r\033[K", out_);
  std::fputs(line.c_str(), out_);
  std::fflush(out_);
  status_shown_ = true;
}

void ProgressDisplay::on_event(const EvalEvent& e) {
  std::lock_guard lock(mutex_);
  char buf[64];
  switch (e.kind) {
    case EvalEvent::Kind::Started:
      running_[e.node] = 0.0;
      break;
    case EvalEvent::Kind::Progress:
      running_[e.node] = e.fraction;
      break;
    case EvalEvent::Kind::Finished:
      running_.erase(e.node);
      ++done_;
      std::snprintf(buf, sizeof buf, "%9.1f ms  ", e.milliseconds);
      print_line_locked(std::string("  computed ") + buf + e.node);
      break;
    case EvalEvent::Kind::Cached:
      ++done_;
      print_line_locked("  cached                " + e.node);
      break;
    case EvalEvent::Kind::Failed:
      running_.erase(e.node);
      ++done_;
      print_line_locked("  FAILED                " + e.node + ": " + e.message);
      break;
    case EvalEvent::Kind::Skipped:
      ++done_;
      print_line_locked("  skipped               " + e.node + " (" + e.message + ")");
      break;
    case EvalEvent::Kind::Cancelled:
      running_.erase(e.node);
      print_line_locked("  cancelled             " + e.node);
      break;
  }
  redraw_locked(e.kind != EvalEvent::Kind::Progress);
}

void ProgressDisplay::finish() {
  std::lock_guard lock(mutex_);
  if (status_shown_) std::fputs("\r\033[K", out_);
  std::fflush(out_);
  status_shown_ = false;
}

}  // namespace orogen::cli
