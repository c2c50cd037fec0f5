#include "editor/model/build_resolutions.h"

#include "cli/graph_overrides.h"
#include "cli/resolution_presets.h"

namespace orogen::editor {

namespace {

constexpr int kQuickSizes[] = {129, 257, 513, 1025};

}  // namespace

std::string BuildResolution::label() const {
  const std::string size = std::to_string(samples.x) + " x " + std::to_string(samples.y);
  switch (kind) {
    case Kind::File:
      return size + " (the file's)";
    case Kind::Quick:
      return size;
    case Kind::Engine:
      return name + ": " + size;
  }
  return size;
}

std::vector<BuildResolution> build_resolutions(const GraphDomain& domain) {
  std::vector<BuildResolution> out;
  out.push_back({BuildResolution::Kind::File, "", domain.resolution});
  const auto add = [&](BuildResolution::Kind kind, const std::string& name, const std::string& text) {
    std::string error;
    if (const auto r = cli::resolution_for(text, domain.size, error)) out.push_back({kind, name, *r});
  };
  for (int n : kQuickSizes)
    if (n != domain.resolution.x) add(BuildResolution::Kind::Quick, std::to_string(n), std::to_string(n));
  for (const auto& p : cli::resolution_presets()) add(BuildResolution::Kind::Engine, p.name, p.name);
  return out;
}

Graph graph_at_resolution(Graph graph, glm::ivec2 samples) {
  graph.domain.resolution = samples;
  return graph;
}

}  // namespace orogen::editor
