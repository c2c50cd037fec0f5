#pragma once
// Dragging a link between pins. A drag starts from an output (looking for an input), from an unconnected
// input (looking for an output), or from a connected input, which picks its link up: dropping it on
// another input moves it, dropping it on empty canvas detaches it. While dragging, the canvas dims every
// pin compatible() refuses, and drop() refuses a wrong link (type mismatch, cycle) with the reason.
#include <optional>
#include <string>

#include "editor/model/document.h"
#include "editor/model/node_layout.h"

namespace orogen::editor {

class LinkDrag {
 public:
  // nullopt if `pin` is not a pin of the graph.
  static std::optional<LinkDrag> begin(const Graph& graph, const PinId& pin);

  // The end of the link that stays put while the other follows the mouse.
  const PinId& anchor() const { return anchor_; }
  // The input whose existing link was picked up, if any.
  const std::optional<PinId>& detached() const { return detached_; }
  // The type of value the dragged link carries.
  PortType type() const { return type_; }

  // Empty if dropping on `pin` makes a valid link, else why not.
  std::string check(const Graph& graph, const PinId& pin) const;
  bool compatible(const Graph& graph, const PinId& pin) const { return check(graph, pin).empty(); }

  // Ends the drag on `target` (or on empty canvas) and applies the result to the document as one undo
  // step. Returns "" on success or when nothing needed doing, else why the link was refused (the document
  // is then unchanged).
  std::string drop(Document& document, const std::optional<PinId>& target) const;

 private:
  PinId anchor_;
  std::optional<PinId> detached_;
  PortType type_ = PortType::Heightfield;
};

}  // namespace orogen::editor
