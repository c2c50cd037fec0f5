#pragma once
// Geometry of nodes on the canvas, in world units (pixels at zoom 1): the node box, its title bar, pin
// positions and the status line. The UI draws with it and the interaction code hit-tests with it, so what
// you see is exactly what you click. Text widths use the metrics of ImGui's default font (ProggyClean,
// monospace, 7 px per glyph at 13 px), so the layout is computed without a window.
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "editor/model/rect.h"
#include "graph/graph.h"

namespace orogen::editor {

struct NodeMetrics {
  static constexpr double kGlyphWidth = 7.0;
  static constexpr double kFontSize = 13.0;
  static constexpr double kTitleHeight = 24.0;
  static constexpr double kRowHeight = 20.0;
  static constexpr double kStatusHeight = 20.0;
  static constexpr double kPinRadius = 5.5;
  static constexpr double kMinWidth = 150.0;
  static constexpr double kMaxWidth = 340.0;
  static constexpr double kPadding = 10.0;
  static constexpr double kThumbnailHeight = 96.0;  // the picture of a field or image output, under the pins
};

// A pin: one input or output port of a node.
struct PinId {
  std::string node;
  std::string port;
  bool output = false;
  bool operator==(const PinId&) const = default;
};

struct PinLayout {
  PinId pin;
  PortType type = PortType::Heightfield;
  glm::dvec2 position{0.0};  // centre of the pin circle, on the node's edge
};

struct NodeLayout {
  std::string id;
  Rect rect;    // the whole node
  Rect title;   // the title bar
  Rect status;  // the status line at the bottom (time, progress bar)
  std::optional<Rect>
      thumbnail;  // between the pins and the status line, for nodes with a field, image, points or curves output
  std::vector<PinLayout> inputs, outputs;
  const PinLayout* find_pin(const std::string& port, bool output) const;
};

// Width of a text at the canvas font size, in world units. The UI measures with its real font; headless
// code uses the monospace estimate.
using TextMeasure = std::function<double(std::string_view)>;
double monospace_width(std::string_view text);

// The title text of a node: its id, plus the type when the id does not already say it.
std::string node_title(const Node& node);
// With `thumbnails`, nodes with a heightfield, image, points or curves output get room for a picture of it.
NodeLayout layout_node(const Node& node, glm::dvec2 position, const TextMeasure& measure = monospace_width,
                       bool thumbnails = false);

// Positions for nodes the file gives none: columns by depth from the sources, rows in graph order, to the
// right of / below what is already placed.
std::map<std::string, glm::dvec2> auto_positions(const Graph& graph);
// Gives every unplaced node of `graph` an auto position (opening files written by hand or the CLI).
void place_unpositioned_nodes(Graph& graph);
// Nodes grow by their thumbnail: moves nodes down (top to bottom, never up, keeping their order) so that
// none overlaps another once thumbnails are shown, in files laid out without them. Returns how many moved.
std::size_t make_room_for_thumbnails(Graph& graph, double margin = 12.0);

// The layout of every node of a graph, in drawing order (later nodes drawn on top).
class CanvasLayout {
 public:
  CanvasLayout() = default;
  explicit CanvasLayout(const Graph& graph) { build(graph); }
  void build(const Graph& graph, const TextMeasure& measure = monospace_width, bool thumbnails = false);

  const std::vector<NodeLayout>& nodes() const { return nodes_; }
  const NodeLayout* find(const std::string& id) const;

  // The topmost node under a world point.
  std::optional<std::string> node_at(glm::dvec2 world) const;
  // The nearest pin within `radius` (world units) of a world point.
  std::optional<PinLayout> pin_at(glm::dvec2 world, double radius) const;
  // Nodes whose box overlaps `world` (box selection).
  std::vector<std::string> nodes_in(const Rect& world) const;
  // Bounding box of the given nodes (all with an empty list); nullopt if none.
  std::optional<Rect> bounds(const std::vector<std::string>& ids = {}) const;

 private:
  std::vector<NodeLayout> nodes_;
  std::map<std::string, std::size_t> index_;
};

}  // namespace orogen::editor
