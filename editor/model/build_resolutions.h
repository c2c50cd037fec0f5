#pragma once
// The resolutions Build offers: the file's own, quick builds to check a result (129 to 1025 samples along x),
// and the sizes game engines import (the CLI's --resolution presets, cli/resolution_presets.h, one table for
// both). Every choice keeps the graph's world rectangle and square cells: y follows the domain's aspect as
// `orogen eval --resolution N` does (cli/graph_overrides.h, resolution_for); a size that cannot keep the cells
// square on this domain is not offered.
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/graph.h"

namespace orogen::editor {

struct BuildResolution {
  enum class Kind { File, Quick, Engine };
  Kind kind = Kind::File;
  std::string name;  // "" for the file's, "129" for a quick one, the preset's name ("unreal-1009")
  glm::ivec2 samples{0};
  std::string label() const;  // "257 x 257 (the file's)", "129 x 129", "unreal-1009: 1009 x 1009"
};

// The file's resolution first, then the quick sizes (other than the file's), then the engines' presets.
std::vector<BuildResolution> build_resolutions(const GraphDomain& domain);

// The graph to build at `samples` (the same world rectangle).
Graph graph_at_resolution(Graph graph, glm::ivec2 samples);

}  // namespace orogen::editor
