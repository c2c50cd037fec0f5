#include "editor/model/link_drag.h"

namespace orogen::editor {

std::optional<LinkDrag> LinkDrag::begin(const Graph& graph, const PinId& pin) {
  const Node* node = graph.find(pin.node);
  if (!node) return std::nullopt;
  LinkDrag drag;
  if (pin.output) {
    const auto* decl = node->type->find_output(pin.port);
    if (!decl) return std::nullopt;
    drag.anchor_ = pin;
    drag.type_ = decl->type;
    return drag;
  }
  const auto* decl = node->type->find_input(pin.port);
  if (!decl) return std::nullopt;
  drag.type_ = decl->type;
  if (auto it = node->inputs.find(pin.port); it != node->inputs.end()) {
    drag.anchor_ = {it->second.node, it->second.port, true};
    drag.detached_ = pin;
  } else {
    drag.anchor_ = pin;
  }
  return drag;
}

std::string LinkDrag::check(const Graph& graph, const PinId& pin) const {
  if (pin.output == anchor_.output)
    return anchor_.output ? "connect an output to an input" : "connect an input to an output";
  const PinId& out = anchor_.output ? anchor_ : pin;
  const PinId& in = anchor_.output ? pin : anchor_;
  return graph.check_link(PortRef{out.node, out.port}, in.node, in.port);
}

std::string LinkDrag::drop(Document& document, const std::optional<PinId>& target) const {
  if (!target) {
    if (detached_) document.disconnect(detached_->node, detached_->port);
    return {};
  }
  if (detached_ && *target == *detached_) return {};  // put back where it was
  if (auto why = check(document.graph(), *target); !why.empty()) return why;
  const PinId& out = anchor_.output ? anchor_ : *target;
  const PinId& in = anchor_.output ? *target : anchor_;
  const PortRef from{out.node, out.port};
  document.edit(detached_ ? "Move link to " + in.node + "." + in.port
                          : "Connect " + from.str() + " to " + in.node + "." + in.port,
                [&](Graph& g) {
                  if (detached_) g.disconnect(detached_->node, detached_->port);
                  g.connect(from, in.node, in.port);
                });
  return {};
}

}  // namespace orogen::editor
