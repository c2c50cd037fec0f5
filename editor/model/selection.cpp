#include "editor/model/selection.h"

namespace orogen::editor {

std::vector<std::string> Selection::ordered(const Graph& graph) const {
  std::vector<std::string> out;
  for (const auto& n : graph.nodes())
    if (contains(n.id)) out.push_back(n.id);
  return out;
}

void Selection::clear() {
  ids_.clear();
  active_.clear();
}

void Selection::select_only(const std::string& id) {
  ids_ = {id};
  active_ = id;
}

void Selection::add(const std::string& id) {
  ids_.insert(id);
  active_ = id;
}

void Selection::toggle(const std::string& id) {
  if (ids_.erase(id)) {
    if (active_ == id) active_ = ids_.empty() ? std::string() : *ids_.rbegin();
  } else {
    add(id);
  }
}

void Selection::set(const std::vector<std::string>& ids) {
  ids_ = std::set<std::string>(ids.begin(), ids.end());
  active_ = ids.empty() ? std::string() : ids.back();
}

void Selection::prune(const Graph& graph) {
  std::erase_if(ids_, [&](const std::string& id) { return !graph.find(id); });
  if (!contains(active_)) active_ = ids_.empty() ? std::string() : *ids_.rbegin();
}

}  // namespace orogen::editor
