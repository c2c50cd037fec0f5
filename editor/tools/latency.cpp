// orogen-editor-latency: how fast the editor's preview follows an edit, and whether the UI thread stays
// free while a build runs. A harness, not a test: it prints figures.
//
//   orogen-editor-latency [--graph FILE] [--node ID] [--param NODE.PARAM] [--iterations N]
//                         [--resolution N] [--build-resolution N]
//
// 1. Edit latency: a parameter change (a new value each time, so never a cache hit) to the updated
//    preview of the previewed node at preview resolution: the EvaluationController's background run plus
//    turning the heightfield into preview pixels (colour map + hillshade) on the UI thread. The GL upload
//    is not included (no window here); it is a glTexSubImage2D of 1 MB.
// 2. Undo latency: setting the parameter back, a cache hit.
// 3. UI thread during a build: a full-resolution build runs in the background while a simulated 60 Hz UI
//    loop calls what the editor calls every frame (node states, build status, preview, and a preview
//    request after an edit every 10th frame); the time each frame spends in those calls.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "editor/model/document.h"
#include "editor/model/evaluation_controller.h"
#include "editor/model/preview_image.h"
#include "graph/registry.h"

using namespace orogen;
using namespace orogen::editor;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct Summary {
  double min = 0, median = 0, p90 = 0, max = 0, mean = 0;
};
Summary summarise(std::vector<double> v) {
  Summary s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  s.median = v[v.size() / 2];
  s.p90 = v[std::min(v.size() - 1, v.size() * 9 / 10)];
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  return s;
}
void print(const char* what, const Summary& s, const char* unit = "ms") {
  std::printf("  %-44s median %8.2f %s   p90 %8.2f   min %8.2f   max %8.2f   mean %8.2f\n", what, s.median, unit, s.p90,
              s.min, s.max, s.mean);
}

// The heightfield the editor would preview: the one the graph writes, else the last one.
std::string default_node(const Graph& g) {
  const auto order = g.topological_order();
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const Node& n = g.at(*it);
    if (!n.type->writes_files) continue;
    for (const auto& [port, src] : n.inputs)
      if (g.at(src.node).type->find_output(src.port)->type == PortType::Heightfield) return src.node;
  }
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (!g.at(*it).type->outputs.empty() && g.at(*it).type->outputs.front().type == PortType::Heightfield) return *it;
  throw std::runtime_error("the graph has no heightfield to preview");
}

// A float parameter of the most upstream ancestor of `node` (an edit there recomputes the whole chain).
std::pair<std::string, std::string> default_param(const Graph& g, const std::string& node) {
  const auto up = g.upstream(node);
  for (const auto& id : g.topological_order())
    if (std::find(up.begin(), up.end(), id) != up.end() || id == node)
      for (const auto& p : g.at(id).type->params)
        if (p.type == ParamType::Float) return {id, p.name};
  throw std::runtime_error("no float parameter upstream of " + node);
}

ParamValue nudged(const ParamDecl& decl, const ParamValue& v, int k) {
  switch (decl.type) {
    case ParamType::Float: {
      const double x = std::get<double>(v);
      const double hi = decl.soft_max.value_or(decl.max.value_or(1e9));
      double step = std::max(std::abs(x) * 0.003, 1e-3) * (k + 1);
      double y = x + step;
      if (y > hi) y = x - step;
      return std::clamp(y, decl.min.value_or(-1e300), decl.max.value_or(1e300));
    }
    case ParamType::Int:
      return std::get<std::int64_t>(v) + ((k % 2) ? -1 : 1);
    case ParamType::Seed:
      return std::get<std::uint64_t>(v) + static_cast<std::uint64_t>(k) + 1;
    default:
      throw std::runtime_error("--param must name a float, int or seed parameter");
  }
}

// Requests a preview and waits for its result (the UI would poll each frame; we poll every 0.2 ms).
double timed_preview(EvaluationController& ec, const Graph& g, const std::string& node, std::uint64_t revision,
                     double* pixels_ms) {
  const auto t0 = Clock::now();
  ec.request_preview(g, {node}, revision);
  std::shared_ptr<const PreviewResult> r;
  for (;;) {
    r = ec.preview();
    if (r && r->revision == revision) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  const auto& out = r->outputs.at(node).at(0);
  const auto t1 = Clock::now();
  const auto px = render_heightfield(*std::get<HeightfieldPtr>(out), {});
  if (pixels_ms) *pixels_ms = ms_since(t1);
  if (px.rgba.empty()) throw std::runtime_error("empty preview");
  return ms_since(t0);
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path graph_file = std::filesystem::path(OROGEN_SOURCE_DIR) / "graphs" / "terrain.json";
  std::string node, param;
  int iterations = 20, resolution = 512, build_resolution = 2048;
  CLI::App cli{"Measures the editor's edit-to-preview latency and the UI thread's freedom during a build"};
  cli.add_option("--graph", graph_file, "Graph file")->check(CLI::ExistingFile);
  cli.add_option("--node", node, "Previewed node (default: the heightfield the graph writes)");
  cli.add_option("--param", param, "NODE.PARAM edited (default: a float parameter of the most upstream source)");
  cli.add_option("--iterations", iterations, "Edits measured")->check(CLI::Range(1, 10000));
  cli.add_option("--resolution", resolution, "Preview resolution (samples on the longer side)")
      ->check(CLI::Range(16, 8192));
  cli.add_option("--build-resolution", build_resolution, "Resolution of the background build (0: skip)")
      ->check(CLI::Range(0, 32768));
  CLI11_PARSE(cli, argc, argv);

  try {
    Document doc = Document::open(graph_file);
    Graph graph = doc.graph();
    if (node.empty()) node = default_node(graph);
    std::string edit_node, edit_param;
    if (param.empty()) {
      std::tie(edit_node, edit_param) = default_param(graph, node);
    } else {
      const auto dot = param.find('.');
      if (dot == std::string::npos) throw std::runtime_error("--param takes NODE.PARAM");
      edit_node = param.substr(0, dot);
      edit_param = param.substr(dot + 1);
    }
    const ParamDecl* decl = graph.at(edit_node).type->find_param(edit_param);
    if (!decl) throw std::runtime_error("no parameter " + param);

    EvaluationController ec;
    ec.set_preview_resolution(resolution);
    const Domain pd = ec.preview_domain(graph.domain);
    std::printf("graph %s: %zu nodes; preview of '%s' at %d x %d; editing %s.%s; %u hardware threads\n",
                graph_file.filename().string().c_str(), graph.nodes().size(), node.c_str(), pd.width(), pd.height(),
                edit_node.c_str(), edit_param.c_str(), std::thread::hardware_concurrency());

    std::uint64_t revision = 1;
    const double cold = timed_preview(ec, graph, node, revision++, nullptr);
    std::printf("  first preview (cold cache): %.1f ms\n", cold);
    const ParamValue original = graph.param(edit_node, edit_param);
    std::vector<double> edit_ms, pixel_ms, undo_ms;
    std::size_t recomputed = 0;
    for (int k = 0; k < iterations; ++k) {
      graph.set_param(edit_node, edit_param, nudged(*decl, original, k));
      double px = 0;
      edit_ms.push_back(timed_preview(ec, graph, node, revision++, &px));
      pixel_ms.push_back(px);
      recomputed = 0;
      for (const auto& [id, r] : ec.preview()->reports) recomputed += r.status == NodeStatus::Computed;
      graph.set_param(edit_node, edit_param, original);
      undo_ms.push_back(timed_preview(ec, graph, node, revision++, nullptr));
    }
    std::printf("edit -> updated preview (%d edits, %zu nodes recomputed each):\n", iterations, recomputed);
    print("total (evaluation + preview pixels)", summarise(edit_ms));
    print("of which preview pixels (color map+hillshade)", summarise(pixel_ms));
    print("undo -> preview (cache hit)", summarise(undo_ms));

    if (build_resolution > 0) {
      Graph build_graph = graph;
      build_graph.domain.resolution = {build_resolution, build_resolution};
      OutputPolicy policy;
      policy.output_dir = std::filesystem::temp_directory_path() / "orogen-latency-build";
      const auto t0 = Clock::now();
      ec.start_build(build_graph, policy);
      std::vector<double> frame_ms;
      int frame = 0;
      std::size_t previews = 0;
      while (ec.build_status().running || frame == 0) {
        const auto f0 = Clock::now();
        // What the editor's UI thread asks of the model each frame.
        auto states = ec.node_states();
        auto build = ec.build_status();
        auto preview = ec.preview();
        if (frame % 10 == 0) {
          graph.set_param(edit_node, edit_param, nudged(*decl, original, frame));
          ec.request_preview(graph, {node}, revision++);
          ++previews;
        }
        frame_ms.push_back(ms_since(f0));
        (void)states;
        (void)build;
        (void)preview;
        ++frame;
        std::this_thread::sleep_until(f0 + std::chrono::microseconds(16667));
      }
      const double build_ms = ms_since(t0);
      const auto status = ec.build_status();
      std::printf("UI thread while building at %d x %d (%s in %.1f s, %d frames, %zu preview requests meanwhile):\n",
                  build_resolution, build_resolution, status.ok ? "ok" : "FAILED", build_ms / 1000.0, frame, previews);
      print("model calls per frame", summarise(frame_ms));
      ec.wait_idle();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "orogen-editor-latency: %s\n", e.what());
    return 1;
  }
  return 0;
}
