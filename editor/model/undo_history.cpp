#include "editor/model/undo_history.h"

#include <algorithm>

namespace orogen::editor {

namespace {
const std::string kEmpty;
}

std::uint64_t UndoHistory::record(const Graph& before, std::uint64_t before_state, std::string label,
                                  std::string merge_key) {
  // State ids only grow, so an id is never reused for a different graph (the dirty flag relies on it).
  next_state_ = std::max(next_state_, before_state + 1);
  const std::uint64_t new_state = next_state_++;
  redo_.clear();
  if (merge_open_ && !merge_key.empty() && merge_key == open_merge_key_ && !undo_.empty()) return new_state;
  undo_.push_back({before, before_state, std::move(label)});
  if (undo_.size() > limit_) undo_.pop_front();
  open_merge_key_ = std::move(merge_key);
  merge_open_ = !open_merge_key_.empty();
  return new_state;
}

const std::string& UndoHistory::undo_label() const { return undo_.empty() ? kEmpty : undo_.back().label; }
const std::string& UndoHistory::redo_label() const { return redo_.empty() ? kEmpty : redo_.back().label; }

std::optional<UndoHistory::Restored> UndoHistory::undo(const Graph& current, std::uint64_t current_state) {
  if (undo_.empty()) return std::nullopt;
  Step step = std::move(undo_.back());
  undo_.pop_back();
  merge_open_ = false;
  redo_.push_back({current, current_state, step.label});
  return Restored{std::move(step.graph), step.state};
}

std::optional<UndoHistory::Restored> UndoHistory::redo(const Graph& current, std::uint64_t current_state) {
  if (redo_.empty()) return std::nullopt;
  Step step = std::move(redo_.back());
  redo_.pop_back();
  merge_open_ = false;
  undo_.push_back({current, current_state, step.label});
  return Restored{std::move(step.graph), step.state};
}

void UndoHistory::clear() {
  undo_.clear();
  redo_.clear();
  merge_open_ = false;
  open_merge_key_.clear();
}

void UndoHistory::for_each_graph(const std::function<void(Graph&)>& fn) {
  for (auto& step : undo_) fn(step.graph);
  for (auto& step : redo_) fn(step.graph);
}

}  // namespace orogen::editor
