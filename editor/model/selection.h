#pragma once
// The selected nodes, plus the active one (the last clicked) whose parameters the inspector shows.
#include <set>
#include <string>
#include <vector>

#include "graph/graph.h"

namespace orogen::editor {

class Selection {
 public:
  bool empty() const { return ids_.empty(); }
  std::size_t size() const { return ids_.size(); }
  bool contains(const std::string& id) const { return ids_.count(id) != 0; }
  const std::set<std::string>& ids() const { return ids_; }
  // The selected ids in graph order (stable for copy, delete and duplicate).
  std::vector<std::string> ordered(const Graph& graph) const;
  // The node the inspector shows: the last one clicked, if still selected.
  const std::string& active() const { return active_; }

  void clear();
  void select_only(const std::string& id);
  void add(const std::string& id);
  void toggle(const std::string& id);  // Shift-click
  void set(const std::vector<std::string>& ids);
  // Forgets ids no longer in the graph (after undo, delete, ...).
  void prune(const Graph& graph);

 private:
  std::set<std::string> ids_;
  std::string active_;
};

}  // namespace orogen::editor
