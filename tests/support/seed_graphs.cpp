#include "support/seed_graphs.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

#include "nodes/io/heightfield_file.h"
#include "support/library_rewrites.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {

SeedRun run_seed_graph(const std::string& file, const std::string& resolution) {
  SeedRun run;
  const auto graph = source_dir() / "graphs" / file;
  // With its library instances expanded and their nodes named as before (support/library_rewrites.h), so the
  // tests read the parameters of the nodes inside them too.
  const auto loaded = load_graph_file(graph);
  if (!loaded.ok()) {
    run.error = loaded.error_text();
    return run;
  }
  run.graph = nlohmann::json::parse(canonical_graph_text(*loaded.graph));
  const auto dir = scratch_dir("seed-" + std::filesystem::path(file).stem().string());
  const auto stats = dir / "stats.json";
  const auto r = run_process(cli_binary(), {"eval", graph.string(), "--resolution", resolution, "-o",
                                            (dir / "out").string(), "--stats", stats.string(), "--quiet"});
  if (r.exit_code != 0) {
    run.error = file + " failed (exit " + std::to_string(r.exit_code) + "): " + r.err;
    return run;
  }
  run.out = dir / "out";
  run.stats = nlohmann::json::parse(read_text(stats));
  // Reports of nodes inside library instances under their names before the rewrite too ("island/biomes" as
  // "biomes"), as in `graph`.
  if (run.stats.contains("reports") && run.stats["reports"].is_object()) {
    auto& reports = run.stats["reports"];
    std::vector<std::pair<std::string, nlohmann::json>> inner;
    for (const auto& [id, report] : reports.items())
      if (const auto slash = id.find('/'); slash != std::string::npos && !reports.contains(id.substr(slash + 1)))
        inner.emplace_back(id.substr(slash + 1), report);
    for (auto& [id, report] : inner) reports[id] = std::move(report);
  }
  return run;
}

const nlohmann::json& node_params(const nlohmann::json& graph, const std::string& id) {
  for (const auto& n : graph.at("nodes"))
    if (n.at("id") == id) return n.at("params");
  throw std::runtime_error("no node " + id);
}

Raster read_raster(const std::filesystem::path& path, int channel) {
  const auto r = read_height_raster(path, channel);
  Raster out;
  out.width = r.width;
  out.height = r.height;
  out.v = r.values;
  return out;
}

Raster read_raster(const std::filesystem::path& path, const std::string& name) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error("cannot open " + path.string());
  const auto& names = in->spec().channelnames;
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::runtime_error(path.string() + " has no channel " + name);
  const int channel = static_cast<int>(it - names.begin());
  in->close();
  return read_raster(path, channel);
}

std::map<std::string, std::vector<double>> read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    std::string name;
    while (std::getline(ss, name, ',')) names.push_back(name);
  }
  std::map<std::string, std::vector<double>> columns;
  for (const auto& n : names) columns[n];
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string cell;
    for (const auto& n : names) {
      std::getline(ss, cell, ',');
      columns[n].push_back(std::stod(cell));
    }
  }
  return columns;
}

}  // namespace orogen::test
