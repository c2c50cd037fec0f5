#pragma once
// The inspector: the active node's parameters, generated from its type's declarations (sliders and drags
// with units and ranges, seeds with re-roll, enum combos, curve, gradient and table editors, file paths), each
// with its description on hover and a reset to the default. With no node selected it shows the graph's
// domain and the preview resolution.
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "editor/model/document.h"
#include "editor/model/evaluation_controller.h"
#include "editor/model/selection.h"
#include "editor/ui/file_dialog.h"

namespace orogen::editor {

class Inspector {
 public:
  explicit Inspector(EvaluationController& evaluation) : evaluation_(evaluation) {}
  void draw(Document& document, Selection& selection);
  // What the "Enter", "Open asset" and "Make unique" buttons of a subgraph instance do (the app's navigation,
  // File > Open, SubgraphNavigator::make_unique). Without make_unique, make_unique_node on the document.
  void set_subgraph_actions(std::function<void(const std::string&)> enter,
                            std::function<void(const std::filesystem::path&)> open_asset,
                            std::function<void(const std::string&)> make_unique = {}) {
    enter_ = std::move(enter);
    open_asset_ = std::move(open_asset);
    make_unique_ = std::move(make_unique);
  }

 private:
  void draw_node(Document& document, Selection& selection, const Node& node);
  void draw_param(Document& document, const Node& node, const ParamDecl& decl);
  // A table parameter below the others, at the panel's full width (editor/ui/table_editor.h).
  void draw_table_param(Document& document, const Node& node, const ParamDecl& decl);
  void draw_graph(Document& document);
  // Applies a value, reporting a refused one under the parameter.
  void apply(Document& document, const Node& node, const ParamDecl& decl, const ParamValue& value, bool gesture);

  EvaluationController& evaluation_;
  std::function<void(const std::string&)> enter_;
  std::function<void(const std::filesystem::path&)> open_asset_;
  std::function<void(const std::string&)> make_unique_;
  FileDialog file_dialog_;
  std::string browse_node_, browse_param_;
  std::map<std::string, std::string> text_;  // in-progress text of string and path fields, by node.param
  std::string rename_of_, rename_text_;
  std::string error_key_, error_;
  // Node descriptions take at most this many lines unless the type's is shown whole ("more").
  static constexpr int kDescriptionLines = 3;
  std::string description_open_;  // the node type whose description is shown whole
};

}  // namespace orogen::editor
