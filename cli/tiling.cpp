#include "cli/tiling.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <glm/common.hpp>

#include "cli/graph_overrides.h"
#include "graph/tile_graph.h"
#include "nodes/io/file_extension.h"

namespace orogen::cli {

namespace {

constexpr int kMaxTiles = 4096;

std::optional<int> parse_int(std::string_view s) {
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// Splits "AsepB" at the first separator from `seps`; nullopt if there is none.
std::optional<std::pair<std::string, std::string>> split_pair(const std::string& text, const char* seps) {
  const auto at = text.find_first_of(seps);
  if (at == std::string::npos) return std::nullopt;
  return std::make_pair(text.substr(0, at), text.substr(at + 1));
}

bool needs_whole_domain(const Graph& graph, const Node& node) {
  return !node.type->writes_files && !node.type->domain_independent &&
         node.type->reach_for(graph.effective_params(node)).is_global();
}

bool is_raster(const PortDecl& p) { return p.type == PortType::Heightfield || p.type == PortType::Image; }

// Whether a node has an output that can be cut into tiles (a raster on the domain's lattice).
bool has_raster_output(const NodeType& type) {
  return !type.own_lattice && std::any_of(type.outputs.begin(), type.outputs.end(), is_raster);
}

// Points are cut too: a node evaluated on a tile's domain gets the points of a larger domain's result that lie
// in its own (evaluator/domain_crop.h).
bool has_points_output(const NodeType& type) {
  return std::any_of(type.outputs.begin(), type.outputs.end(),
                     [](const PortDecl& p) { return p.type == PortType::Points; });
}

// Per tile for its parameter values: tile invariant, a tile's evaluation is the untiled result's part of it.
bool tile_invariant(const Graph& graph, const Node& node) {
  return node.type->distribution_for(graph.effective_params(node)) == Distribution::PerTile;
}

// "mesh 'out'", "curves 'rivers'": the outputs of `type` that cannot be cut into the tiles.
std::string other_outputs(const NodeType& type) {
  std::vector<std::string> parts;
  for (const auto& p : type.outputs)
    if (p.type == PortType::Report || p.type == PortType::Points) {
      continue;
    } else if (!is_raster(p)) {
      std::string t(to_string(p.type));
      std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
      parts.push_back(t + " '" + p.name + "'");
    } else if (type.own_lattice) {
      parts.push_back("'" + p.name + "' on its own lattice");
    }
  std::string text;
  for (std::size_t k = 0; k < parts.size(); ++k)
    text += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
  return text;
}

// Evaluated on the whole domain and cut into the tiles (GlobalNodes::Whole, not tile invariant, and a raster or
// points output to cut).
bool evaluated_whole(const Graph& graph, const Node& node, GlobalNodes global) {
  if (global != GlobalNodes::Whole || !needs_whole_domain(graph, node) || tile_invariant(graph, node)) return false;
  return has_raster_output(*node.type) || has_points_output(*node.type);
}

// Reach::halo, computed in double and capped at `cap` (a halo wider than the domain is the whole domain),
// so an extreme radius on a fine lattice cannot overflow; 0 for point-wise and global reaches.
glm::ivec2 capped_halo(const Reach& reach, glm::dvec2 spacing, glm::ivec2 cap) {
  if (reach.kind != ReachKind::Local) return {0, 0};
  glm::ivec2 h;
  for (int k = 0; k < 2; ++k) {
    const double v = std::ceil(reach.metres / spacing[k] - 1e-9) + reach.samples;  // as Reach::halo
    h[k] = std::isfinite(v) ? static_cast<int>(std::clamp(v, 0.0, static_cast<double>(cap[k]))) : cap[k];
  }
  return h;
}

}  // namespace

std::optional<glm::ivec2> parse_tile_counts(const std::string& text, std::string& error) {
  const auto parts = split_pair(text, "xX");
  std::optional<int> n, m;
  if (parts) n = parse_int(parts->first), m = parse_int(parts->second);
  if (!n || !m) {
    error = "--tiles '" + text + "': expected NxM, the tile counts along x and y (e.g. 4x4)";
    return std::nullopt;
  }
  if (*n < 1 || *m < 1 || *n > kMaxTiles || *m > kMaxTiles) {
    error = "--tiles " + text + ": tile counts must be from 1 to " + std::to_string(kMaxTiles) + " along each axis";
    return std::nullopt;
  }
  return glm::ivec2(*n, *m);
}

std::optional<glm::ivec2> parse_tile_index(const std::string& text, glm::ivec2 counts, std::string& error) {
  const auto parts = split_pair(text, ",");
  std::optional<int> i, j;
  if (parts) i = parse_int(parts->first), j = parse_int(parts->second);
  if (!i || !j) {
    error = "--tile '" + text + "': expected I,J, the tile's column and row counted from 0 (e.g. 0,2)";
    return std::nullopt;
  }
  if (*i < 0 || *j < 0 || *i >= counts.x || *j >= counts.y) {
    error = "--tile " + text + " is outside the " + std::to_string(counts.x) + "x" + std::to_string(counts.y) +
            " tiles of --tiles: I must be from 0 to " + std::to_string(counts.x - 1) + " and J from 0 to " +
            std::to_string(counts.y - 1);
    return std::nullopt;
  }
  return glm::ivec2(*i, *j);
}

std::optional<glm::dvec2> parse_number_pair(const std::string& text, const std::string& option, bool positive,
                                            std::string& error) {
  const auto parts = split_pair(text, ",");
  std::optional<double> x, y;
  if (parts)
    x = parse_number(parts->first, -kMaxCoordinate, kMaxCoordinate),
    y = parse_number(parts->second, -kMaxCoordinate, kMaxCoordinate);
  if (!x || !y) {
    error = option + " '" + text + "': expected two numbers X,Y in metres (e.g. " +
            (positive ? "4096,2048" : "-1024,512") + "), each within +/-1e12";
    return std::nullopt;
  }
  if (positive && !(*x > 0.0 && *y > 0.0)) {
    error = option + " " + text + ": the width and height must be greater than 0 m";
    return std::nullopt;
  }
  return glm::dvec2(*x, *y);
}

std::string check_tile_counts(glm::ivec2 resolution, glm::ivec2 counts) {
  for (int k = 0; k < 2; ++k) {
    if (counts[k] <= resolution[k] - 1) continue;
    std::ostringstream s;
    s << "--tiles " << counts.x << "x" << counts.y << " on " << resolution.x << "x" << resolution.y
      << " samples: " << counts[k] << " tiles along " << (k == 0 ? "x" : "y") << " would have fewer than 2 samples "
      << "each (neighbors share their border samples, so " << resolution[k] << " samples allow at most "
      << std::max(resolution[k] - 1, 0) << " tiles); use fewer tiles or a higher --resolution";
    return s.str();
  }
  return {};
}

TileWindow tile_window(glm::ivec2 resolution, glm::ivec2 counts, glm::ivec2 index) {
  TileWindow w;
  w.index = index;
  for (int k = 0; k < 2; ++k) {
    // Boundaries from integers: tile I covers [floor(I (W-1) / N), floor((I+1) (W-1) / N)].
    const auto edge = [&](int t) {
      return static_cast<int>(static_cast<long long>(t) * (resolution[k] - 1) / counts[k]);
    };
    w.first[k] = edge(index[k]);
    w.size[k] = edge(index[k] + 1) - w.first[k] + 1;
  }
  return w;
}

std::string tile_suffix(glm::ivec2 index) { return "_x" + std::to_string(index.x) + "_y" + std::to_string(index.y); }

std::string with_suffix(const std::string& path, const std::string& suffix) {
  const std::filesystem::path p(path);
  const std::string ext = p.extension().string();
  return path.substr(0, path.size() - ext.size()) + suffix + ext;
}

void add_output_suffix(Graph& graph, const std::string& suffix) {
  std::vector<std::pair<std::string, std::string>> edits;  // (node, param)
  for (const auto& node : graph.nodes())
    for (const auto& decl : node.type->params)
      if (decl.output_file) edits.emplace_back(node.id, decl.name);
  // A mesh's draped texture (WriteMesh `texture`, relative to the mesh file) that names an image the graph
  // writes refers to that image's tile: it gets the same suffix.
  std::set<std::string> written;
  for (const auto& [id, name] : edits)
    written.insert(
        std::filesystem::path(std::get<std::string>(graph.param(id, name))).lexically_normal().generic_string());
  std::vector<std::pair<std::string, std::string>> textures;  // (node, new texture)
  for (const auto& node : graph.nodes()) {
    if (!node.type->find_param("texture") || !node.type->find_param("path")) continue;
    const auto* texture = std::get_if<std::string>(&graph.param(node.id, "texture"));
    const auto* path = std::get_if<std::string>(&graph.param(node.id, "path"));
    if (!texture || !path || texture->empty()) continue;
    const auto image = (std::filesystem::path(*path).parent_path() / *texture).lexically_normal().generic_string();
    if (written.count(image)) textures.emplace_back(node.id, with_suffix(*texture, suffix));
  }
  for (const auto& [id, name] : edits)
    graph.set_param(id, name, with_suffix(std::get<std::string>(graph.param(id, name)), suffix));
  for (const auto& [id, texture] : textures) graph.set_param(id, "texture", texture);
}

std::optional<GlobalNodes> parse_global_nodes(const std::string& text) {
  if (text == "whole") return GlobalNodes::Whole;
  if (text == "tile") return GlobalNodes::PerTile;
  return std::nullopt;
}

std::vector<std::string> whole_domain_nodes(const Graph& graph) {
  std::vector<std::string> ids;
  for (const auto& node : graph.nodes())
    if (needs_whole_domain(graph, node)) ids.push_back(node.id);
  return ids;
}

std::set<std::string> across_tile_nodes(const Graph& graph, const Domain& full, GlobalNodes global) {
  std::set<std::string> across;
  if (global != GlobalNodes::Whole) return across;
  for (const auto& node : graph.nodes()) {
    const auto& outputs = node.type->outputs;
    // Rasters (heightfields and images) are cut into the tiles and put together; curves (RiverExtract's network) and
    // reports (DrainageMetrics', KMeansClusters') are given whole to every tile. (Evaluated whole, the node has a
    // raster output on the domain's lattice or points, which are not among these.)
    const bool rasters = std::all_of(outputs.begin(), outputs.end(), [](const PortDecl& p) {
      return is_raster(p) || p.type == PortType::Curves || p.type == PortType::Report;
    });
    // Inputs on a lattice of their own (resampled by the node) cannot be cut into the tiles.
    const bool lattice_inputs = std::all_of(node.inputs.begin(), node.inputs.end(), [&](const auto& in) {
      return !graph.at(in.second.node).type->own_lattice;
    });
    if (!evaluated_whole(graph, node, global) || !rasters || !lattice_inputs) continue;
    const auto refused = tile_graph_unlinked_inputs(node.type->name);
    const bool refused_input_linked = std::any_of(refused.begin(), refused.end(),
                                                  [&](const std::string& port) { return node.inputs.count(port) > 0; });
    const std::vector<ParamValue> params = graph.effective_params(node);
    if (!refused_input_linked && tile_graph_for(node.type->name, ParamView(*node.type, params), full))
      across.insert(node.id);
  }
  // A node whose result some whole-domain node needs is computed on the whole domain for it anyway. Downstream
  // first, so a chain of tile-graph nodes stays across tiles.
  const auto order = graph.topological_order();
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    if (!across.count(*it)) continue;
    for (const auto& down : graph.downstream(*it))
      if (evaluated_whole(graph, graph.at(down), global) && !across.count(down)) {
        across.erase(*it);
        break;
      }
  }
  return across;
}

std::map<std::string, Domain> tile_node_domains(const Graph& graph, const Domain& full, const TileWindow& window,
                                                GlobalNodes global, const std::set<std::string>& across_tiles) {
  const std::vector<std::string> order = graph.topological_order();
  std::map<std::string, std::vector<const Node*>> consumers;
  for (const auto& node : graph.nodes())
    for (const auto& [port, link] : node.inputs) consumers[link.node].push_back(&node);
  // The halo each node's output must be right within, beyond the tile (samples per axis), and its own.
  std::map<std::string, glm::ivec2> need, halo;
  std::map<std::string, Domain> domains;
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const Node& node = graph.at(*it);
    glm::ivec2 n{0, 0};
    for (const Node* c : consumers[node.id]) n = glm::max(n, need.at(c->id) + halo.at(c->id));
    // A whole-domain node evaluated whole: a halo that covers the domain from any tile.
    const glm::ivec2 own =
        evaluated_whole(graph, node, global) && !across_tiles.count(node.id)
            ? full.resolution
            : capped_halo(node.type->reach_for(graph.effective_params(node)), full.spacing, full.resolution);
    // Margins beyond the domain's size change nothing: clamped, so long chains of wide halos cannot overflow.
    need[node.id] = glm::min(n, full.resolution);
    halo[node.id] = glm::min(own, full.resolution);
    const glm::ivec2 margin = need[node.id] + halo[node.id];
    const glm::ivec2 lo = glm::max(window.first - margin, glm::ivec2(0));
    const glm::ivec2 hi = glm::min(window.first + window.size - 1 + margin, full.resolution - 1);
    domains[node.id] = full.subdomain(lo.x, lo.y, hi.x - lo.x + 1, hi.y - lo.y + 1);
  }
  return domains;
}

std::vector<std::string> seam_warnings(const Graph& graph, GlobalNodes global,
                                       const std::set<std::string>& across_tiles) {
  std::vector<std::string> warnings;
  auto quoted_list = [](const std::vector<std::string>& items) {
    std::string text;
    for (std::size_t k = 0; k < items.size(); ++k) text += (k == 0 ? "" : ", ") + items[k];
    return text;
  };
  // Cut from one whole-domain result: seamless, at the whole domain's cost. One warning for all of them.
  std::vector<std::string> whole, whole_uncut;
  for (const auto& id : whole_domain_nodes(graph)) {
    const Node& node = graph.at(id);
    if (!evaluated_whole(graph, node, global) || across_tiles.count(id)) continue;
    whole.push_back("'" + id + "' (" + node.type->name + ")");
    if (const auto others = other_outputs(*node.type); !others.empty()) whole_uncut.push_back("'" + id + "' " + others);
  }
  if (!whole.empty())
    warnings.push_back(std::string(whole.size() == 1 ? "node " : "nodes ") + quoted_list(whole) +
                       (whole.size() == 1 ? " depends" : " depend") +
                       " on the whole domain (reach global): computed once on the whole domain, with what feeds "
                       "them, and cut into the tiles, so the tiles join but these nodes take the whole domain's "
                       "memory and time (share a --cache-dir between --tile jobs to compute them once; "
                       "--global-nodes tile computes them per tile instead, with seams)" +
                       (whole_uncut.empty() ? std::string()
                                            : "; outputs that cannot be cut cover the whole domain in every tile: " +
                                                  quoted_list(whole_uncut)));
  // Computed per tile: not seamless (unless tile invariant). One warning per node, with the writers it reaches.
  for (const auto& id : whole_domain_nodes(graph)) {
    const Node& node = graph.at(id);
    const NodeType& type = *node.type;
    if (evaluated_whole(graph, node, global) || tile_invariant(graph, node)) continue;
    std::vector<std::string> writers;
    for (const auto& down : graph.downstream(id))
      if (graph.at(down).type->writes_files) writers.push_back("'" + down + "'");
    const std::string why =
        global == GlobalNodes::PerTile
            ? "with --global-nodes tile, each tile computes it"
            : "its " + other_outputs(type) + " cannot be cut from a whole-domain result: each tile computes it";
    warnings.push_back("node '" + id + "' (" + type.name + ", reach " +
                       type.reach_for(graph.effective_params(node)).describe() +
                       ") depends on the whole domain: " + why + " from its own part only, so its result" +
                       (writers.empty() ? std::string() : " and the outputs of " + quoted_list(writers)) +
                       " will not join seamlessly across tile borders nor match the untiled build");
  }
  // 16-bit heightfield files mapped over each tile's own range.
  std::vector<std::string> ranged;
  for (const auto& node : graph.nodes()) {
    const NodeType& type = *node.type;
    if (!type.writes_files || !type.find_param("range") || !type.find_param("path")) continue;
    const auto* range = std::get_if<std::string>(&graph.param(node.id, "range"));
    const auto* path = std::get_if<std::string>(&graph.param(node.id, "path"));
    if (!range || !path || *range != "auto") continue;
    const std::string ext = lower_extension(*path);
    if (ext == ".png" || ext == ".raw" || ext == ".r16") ranged.push_back("'" + node.id + "'");
  }
  if (!ranged.empty())
    warnings.push_back(std::string(ranged.size() == 1 ? "writer " : "writers ") + quoted_list(ranged) +
                       (ranged.size() == 1 ? " maps" : " map") +
                       " 16-bit heights over each tile's own range (range 'auto'): neighboring tiles store "
                       "their shared border with different codes; set range to 'fixed' (or write EXR/TIFF) for "
                       "tiles that join");
  return warnings;
}

}  // namespace orogen::cli
