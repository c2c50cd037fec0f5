#pragma once
// Undo and redo of graph edits as whole-graph snapshots.
//
// A graph holds only parameters, links and layout (the heavy data lives in the evaluator's cache), so a
// snapshot per step is cheap and undo restores the exact earlier state: no inverse operations to get wrong.
// Consecutive edits with the same merge key (one parameter drag, one node move) extend the open step
// instead of adding one per frame, until close_merge() ends the gesture.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>

#include "graph/graph.h"

namespace orogen::editor {

class UndoHistory {
 public:
  explicit UndoHistory(std::size_t limit = 1000) : limit_(limit) {}

  // Records that the graph changes from `before` (state id `before_state`) to a new state. Returns the id
  // of the new state. With a merge key equal to that of the open step, the step is extended instead.
  std::uint64_t record(const Graph& before, std::uint64_t before_state, std::string label, std::string merge_key = {});
  // Ends the open gesture: the next record() starts a new step even with the same merge key.
  void close_merge() { merge_open_ = false; }

  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  const std::string& undo_label() const;  // "" if nothing to undo
  const std::string& redo_label() const;

  struct Restored {
    Graph graph;
    std::uint64_t state = 0;
  };
  // The state to go back to; `current` (with id `current_state`) becomes redoable.
  std::optional<Restored> undo(const Graph& current, std::uint64_t current_state);
  std::optional<Restored> redo(const Graph& current, std::uint64_t current_state);

  void clear();
  // Every graph the history holds (undo and redo steps), for changes that are not edits: instances pointed
  // at the new content of an asset file edited elsewhere (Document::rebind_asset).
  void for_each_graph(const std::function<void(Graph&)>& fn);
  std::size_t undo_size() const { return undo_.size(); }
  std::size_t redo_size() const { return redo_.size(); }

 private:
  struct Step {
    Graph graph;  // the state on the other side of this step
    std::uint64_t state = 0;
    std::string label;  // what the step does, for "Undo <label>"
  };
  std::deque<Step> undo_, redo_;
  std::size_t limit_;
  std::uint64_t next_state_ = 1;
  std::string open_merge_key_;
  bool merge_open_ = false;
};

}  // namespace orogen::editor
