#pragma once
// An open graph: the Graph itself, the file it came from, its undo history and whether it has unsaved
// changes. Every change goes through edit(), which applies it to a copy first: a failing edit (a refused
// link, an out-of-range value) leaves the document untouched, and a successful one is one undo step.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "editor/model/undo_history.h"
#include "graph/graph.h"
#include "graph/graph_file.h"
#include "graph/subgraph.h"

namespace orogen::editor {

struct DocumentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Document {
 public:
  Document();  // untitled, empty graph with the default domain
  explicit Document(Graph graph, std::filesystem::path path = {});
  // Loads a graph file. A file with problems (unknown node types, broken links, invalid values) opens with
  // what can be read (LoadOptions::keep_partial) and its problems in load_problems(); the document then
  // differs from its file. Throws DocumentError carrying the diagnostics when nothing can be read (not a
  // graph file, a newer format).
  // With `room_for_thumbnails`, nodes are moved apart so thumbnails fit (make_room_for_thumbnails), as
  // part of opening: not an edit, the document stays clean.
  static Document open(const std::filesystem::path& path, bool room_for_thumbnails = false);

  // What was wrong in the file this document was opened from (empty for a clean file).
  struct LoadProblems {
    std::vector<Diagnostic> diagnostics;
    std::vector<DroppedLink> dropped_links;
    bool empty() const { return diagnostics.empty() && dropped_links.empty(); }
    // The messages about one node (its own diagnostics, and the links into it that were left out).
    std::vector<std::string> for_node(const std::string& id) const;
  };
  const LoadProblems& load_problems() const { return load_problems_; }
  void clear_load_problems() { load_problems_ = {}; }

  const Graph& graph() const { return graph_; }
  const std::filesystem::path& path() const { return path_; }
  bool has_path() const { return !path_.empty(); }
  std::string display_name() const;  // file name, or "Untitled"
  bool dirty() const { return state_ != saved_state_; }
  // Marks the document as differing from its file (a recovered session's work).
  void mark_unsaved() { saved_state_ = ~std::uint64_t(0); }
  // "terrain.json* - Orogen": '*' marks unsaved changes.
  std::string window_title() const;

  // Increases on every change, undo and redo included.
  std::uint64_t revision() const { return revision_; }
  // Increases only when something evaluation depends on changes (nodes, parameters, links, domain), not
  // for layout: moving a node does not trigger a re-evaluation.
  std::uint64_t content_revision() const { return content_revision_; }

  // Applies `fn` to a copy of the graph. If it throws, nothing changes and the exception propagates. An
  // edit that changes nothing records nothing. Edits with the same non-empty merge key merge into one undo
  // step until end_gesture(). Returns whether the graph changed.
  bool edit(const std::string& label, const std::function<void(Graph&)>& fn, const std::string& merge_key = {});
  // Ends a drag: the next edit starts a new undo step.
  void end_gesture() { history_.close_merge(); }

  bool undo();
  bool redo();
  const UndoHistory& history() const { return history_; }

  // Common edits, each one undo step (or one merged gesture when `gesture` is set).
  std::string add_node(const std::string& type_name, glm::dvec2 position);
  void remove_nodes(const std::vector<std::string>& ids);
  void connect(const PortRef& from, const std::string& to_node, const std::string& to_port);
  void disconnect(const std::string& to_node, const std::string& to_port);
  void set_param(const std::string& node, const std::string& name, const ParamValue& value, bool gesture = false);
  void reset_param(const std::string& node, const std::string& name);
  void move_nodes(const std::vector<std::string>& ids, glm::dvec2 delta, bool gesture = false);
  void rename_node(const std::string& id, const std::string& new_id);
  void set_domain(const GraphDomain& domain);

  // Points the subgraph instances of the asset file `file` at `asset`, its new content (an asset edited in
  // the editor, editor/model/subgraph_navigation.h), in the graph and in every undo step: the file is the
  // truth for all of them. Not an edit (nothing to undo, the dirty flag is kept), but a content change.
  // Returns whether any instance was found.
  bool rebind_asset(const std::filesystem::path& file, const SubgraphAsset& asset);
  // The same for an edited embedded asset of this document (its "subgraphs" section): its instances, and the
  // embedded assets that use it, follow. The file must be saved to keep the edit: the document is unsaved.
  bool rebind_embedded(const SubgraphAsset& asset);

  // Atomic writes (save_graph_file). save() needs a path; both throw std::runtime_error on failure and then
  // leave the document dirty.
  void save();
  void save_as(const std::filesystem::path& path);

 private:
  void replace(Graph graph, std::uint64_t state);

  Graph graph_;
  LoadProblems load_problems_;
  std::filesystem::path path_;
  UndoHistory history_;
  std::uint64_t state_ = 0, saved_state_ = 0;
  std::uint64_t revision_ = 0, content_revision_ = 0;
};

// Whether two graphs evaluate the same: equal nodes, parameters, links and domain (layout ignored).
bool same_content(const Graph& a, const Graph& b);

}  // namespace orogen::editor
