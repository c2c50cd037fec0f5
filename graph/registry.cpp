#include "graph/registry.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

namespace orogen {

NodeRegistry& NodeRegistry::instance() {
  static NodeRegistry registry;
  return registry;
}

const NodeType& NodeRegistry::add(NodeType type) {
  check_declaration(type);
  std::unique_lock lock(mutex_);
  for (const auto& t : types_)
    if (t->name == type.name) throw std::logic_error("node type '" + type.name + "' registered twice");
  types_.push_back(std::make_unique<NodeType>(std::move(type)));
  return *types_.back();
}

const NodeType* NodeRegistry::find(std::string_view name) const {
  std::shared_lock lock(mutex_);
  for (const auto& t : types_)
    if (t->name == name) return t.get();
  return nullptr;
}

std::vector<const NodeType*> NodeRegistry::all() const {
  std::vector<const NodeType*> out;
  {
    std::shared_lock lock(mutex_);
    for (const auto& t : types_) out.push_back(t.get());
  }
  std::sort(out.begin(), out.end(), [](const NodeType* a, const NodeType* b) {
    return a->category != b->category ? a->category < b->category : a->name < b->name;
  });
  return out;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string NodeRegistry::closest(std::string_view name) const {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(3, name.size() / 2) + 1;
  std::shared_lock lock(mutex_);
  for (const auto& t : types_) {
    const auto d = edit_distance(name, t->name);
    if (d < best_distance) {
      best_distance = d;
      best = t->name;
    }
  }
  return best;
}

NodeRegistration::NodeRegistration(const char* name, void (*declare)(NodeBuilder&)) {
  NodeType type;
  type.name = name;
  NodeBuilder builder(type);
  if (auto* staging = NodeRegistry::instance().staging()) {
    // A node library is loading: an exception must not leave the library's initialisers (that would end the
    // process); the loader reports it with the library's name.
    try {
      declare(builder);
      staging->types.push_back(std::move(type));
    } catch (const std::exception& e) {
      staging->errors.push_back("node type '" + std::string(name) + "': " + e.what());
    } catch (...) {
      staging->errors.push_back("node type '" + std::string(name) + "': its declaration threw");
    }
    return;
  }
  declare(builder);
  try {
    NodeRegistry::instance().add(std::move(type));
  } catch (const std::exception& e) {
    // A broken declaration is a programming error: fail loudly at start-up, before any graph is read.
    std::fprintf(stderr, "orogen: invalid node declaration: %s\n", e.what());
    std::abort();
  }
}

}  // namespace orogen
