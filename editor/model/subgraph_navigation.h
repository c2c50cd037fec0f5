#pragma once
// Entering subgraphs (Tab or double-click on an instance): the canvas edits the instance's asset file as a
// document of its own, one level per instance entered, with breadcrumbs back out. Edits inside are written to
// the asset file (sync()), and every instance of that asset in the levels above, undo steps included, is
// pointed at the new content, so they all evaluate it. An embedded asset ("#name", made by Make unique) has no
// file: its edits go into the document that holds it (the nearest level above that is a file), which becomes
// unsaved.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "editor/model/document.h"

namespace orogen::editor {

class SubgraphNavigator {
 public:
  explicit SubgraphNavigator(Document& root) : root_(&root) {}

  // Another root document (File > Open, New): every level is left.
  void set_root(Document& root);
  Document& root() { return *root_; }
  // The document the canvas edits: the innermost level, else the root.
  Document& current() { return levels_.empty() ? *root_ : *levels_.back().document; }
  const Document& current() const { return levels_.empty() ? *root_ : *levels_.back().document; }
  bool inside() const { return !levels_.empty(); }
  std::size_t depth() const { return levels_.size(); }

  struct Level {
    std::string instance;                // the instance entered, in the level above
    std::string asset;                   // its asset's name
    std::filesystem::path file;          // empty for an embedded asset
    std::string embedded;                // an embedded asset's name ("#name"): edits go to the document above
    std::unique_ptr<Document> document;  // the asset file, opened (an embedded asset: its nodes, untitled)
    std::uint64_t synced_revision = 0;   // the document revision last written to the file (or refused)
    std::string error;                   // why that revision could not be written
  };
  const std::vector<Level>& levels() const { return levels_; }

  // "terrain.json", then "mountains (eroded_mountain_range)" per level: what the breadcrumbs show.
  std::vector<std::string> breadcrumbs() const;
  // The expanded id of the current level's instance ("a/b"); "" at the root.
  std::string instance_path() const;

  // Enters instance `id` of the current document: opens its asset file. Throws DocumentError when `id` is
  // not an instance or its asset cannot be opened.
  Document& enter(const std::string& id);
  // Leaves the innermost level, syncing it first; false at the root, and when an asset could not be written
  // (sync_error() says why: the edits would be lost, so they must be fixed or undone first).
  bool leave();
  // Leaves levels until `depth` are left (0: the root), or one cannot be left.
  void leave_to(std::size_t depth);

  // Writes every level edited since the last sync to its asset file (an embedded one into the document holding
  // it) and points the instances above at the new content. An asset the edits made invalid (an inner node the interface
  // maps to was deleted, ...) is not written; returns why (empty when everything is written). Cheap when nothing
  // changed.
  std::string sync();
  // Make unique (editor/model/grouping.h) of instance `id` of the current document; inside an embedded asset
  // the copy's name is made free in the document that holds it too. Returns the embedded asset's name.
  std::string make_unique(const std::string& id);

  // The last sync's problem, until a sync succeeds.
  const std::string& sync_error() const { return sync_error_; }

 private:
  Document* root_;
  std::vector<Level> levels_;
  std::string sync_error_;
};

}  // namespace orogen::editor
