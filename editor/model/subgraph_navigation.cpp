#include "editor/model/subgraph_navigation.h"

#include "editor/model/grouping.h"
#include "graph/graph_file.h"
#include "graph/subgraph.h"
#include "graph/subgraph_unique.h"

namespace orogen::editor {

namespace fs = std::filesystem;

namespace {
void add_problem(std::string& problems, const std::string& text) {
  if (text.empty()) return;
  if (!problems.empty()) problems += '\n';
  problems += text;
}
}  // namespace

void SubgraphNavigator::set_root(Document& root) {
  root_ = &root;
  levels_.clear();
  sync_error_.clear();
}

std::vector<std::string> SubgraphNavigator::breadcrumbs() const {
  std::vector<std::string> out{root_->display_name()};
  for (const auto& level : levels_) out.push_back(level.instance + " (" + level.asset + ")");
  return out;
}

std::string SubgraphNavigator::instance_path() const {
  std::string path;
  for (const auto& level : levels_) path += (path.empty() ? "" : "/") + level.instance;
  return path;
}

Document& SubgraphNavigator::enter(const std::string& id) {
  const Node* node = current().graph().find(id);
  if (!node) throw DocumentError("cannot enter '" + id + "': there is no such node");
  const SubgraphAsset* asset = node->type->subgraph;
  if (!asset)
    throw DocumentError("cannot enter '" + id + "': it is a " + node->type->name + ", not a subgraph instance");
  Level level;
  level.instance = id;
  level.asset = asset->name;
  level.file = asset->file;
  if (!asset->embedded.empty()) {
    // Part of the document above: edited in memory, no file to open.
    level.asset = std::string(1, kEmbeddedReferencePrefix) + asset->embedded;
    level.embedded = asset->embedded;
    level.document = std::make_unique<Document>(asset->graph);
    level.synced_revision = level.document->revision();
    levels_.push_back(std::move(level));
    return current();
  }
  level.document = std::make_unique<Document>(Document::open(asset->file));
  if (!level.document->load_problems().empty())
    throw DocumentError("cannot enter '" + id + "': its asset " + asset->file.string() + " has problems:\n" +
                        level.document->load_problems().diagnostics.front().str());
  level.synced_revision = level.document->revision();
  levels_.push_back(std::move(level));
  return current();
}

std::string SubgraphNavigator::make_unique(const std::string& id) {
  // The document whose file holds the current level's embedded assets: the nearest file level above, or the root.
  std::size_t owner = levels_.size();
  while (owner > 0 && !levels_[owner - 1].embedded.empty()) --owner;
  const Document* holder = owner == levels_.size() ? nullptr : owner == 0 ? root_ : levels_[owner - 1].document.get();
  return make_unique_node(current(), id, holder ? &holder->graph() : nullptr);
}

bool SubgraphNavigator::leave() {
  if (levels_.empty()) return false;
  // Edits the file could not take would be lost with the level: stay until they are fixed or undone.
  if (!sync().empty()) return false;
  levels_.pop_back();
  return true;
}

void SubgraphNavigator::leave_to(std::size_t depth) {
  while (levels_.size() > depth && leave()) {}
}

std::string SubgraphNavigator::sync() {
  std::string problems;
  // Innermost first: a level's new asset changes the instances of the level above, whose asset (same file
  // text, new nested content) must then be loaded again too, up to the root.
  bool below_changed = false;
  for (std::size_t k = levels_.size(); k-- > 0;) {
    Level& level = levels_[k];
    Document& doc = *level.document;
    const bool edited = doc.revision() != level.synced_revision;
    if (!edited && !below_changed) {
      add_problem(problems, level.error);  // still not written
      continue;
    }
    level.synced_revision = doc.revision();
    level.error.clear();
    if (!level.embedded.empty()) {
      // Into the document holding it (the nearest file level above, or the root) and the embedded levels
      // between, which hold instances of it too.
      const AssetLoad load = load_embedded_graph(level.embedded, doc.graph());
      if (!load.asset) {
        level.error = "asset '" + level.asset + "' not updated: " + load.error;
        add_problem(problems, level.error);
        below_changed = false;
        continue;
      }
      std::size_t owner = k;
      while (owner > 0 && !levels_[owner - 1].embedded.empty()) --owner;
      try {
        if (owner == 0) root_->rebind_embedded(*load.asset);
        for (std::size_t j = owner == 0 ? 0 : owner - 1; j < k; ++j) levels_[j].document->rebind_embedded(*load.asset);
      } catch (const std::exception& e) {
        level.error = "asset '" + level.asset + "' not updated: " + e.what();
        add_problem(problems, level.error);
        below_changed = false;
        continue;
      }
      below_changed = true;
      continue;
    }
    LoadOptions options;
    options.directory = level.file.parent_path();
    // Loaded as the asset itself would be, so that an instance of it inside it is refused before it is written.
    AssetLoadContext context;
    context.chain.push_back(level.asset);
    context.files.push_back(level.file);
    options.asset_context = &context;
    const LoadResult check = parse_graph(serialize_graph(doc.graph()), options);
    if (!check.ok() || !check.graph->interface) {
      level.error =
          "asset '" + level.asset + "' not saved: " + (check.ok() ? "it lost its interface" : check.error_text());
      add_problem(problems, level.error);
      below_changed = false;  // the levels above keep the content the file still has
      continue;
    }
    try {
      doc.save();
    } catch (const std::exception& e) {
      level.error = "asset '" + level.asset + "' not saved: " + e.what();
      add_problem(problems, level.error);
      below_changed = false;
      continue;
    }
    const AssetLoad load = load_subgraph_asset(level.file.string(), level.file.parent_path());
    if (!load.asset) {
      level.error = load.error;
      add_problem(problems, level.error);
      below_changed = false;
      continue;
    }
    // Every level above may use the asset (the root and the asset entered from it both can).
    root_->rebind_asset(level.file, *load.asset);
    for (std::size_t j = 0; j < k; ++j) levels_[j].document->rebind_asset(level.file, *load.asset);
    // The level doc's own revision moved with the save only if something else changed: keep it as synced.
    level.synced_revision = doc.revision();
    below_changed = true;
  }
  sync_error_ = problems;
  return problems;
}

}  // namespace orogen::editor
