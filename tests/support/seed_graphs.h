#pragma once
// Helpers for the promise tests of the seed graphs (tests/test_seed_*.cpp): evaluate a graph file of graphs/
// with the `orogen` command at a reduced resolution, and read back what its writers produced.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace orogen::test {

struct SeedRun {
  std::filesystem::path out;  // the output directory
  nlohmann::json graph;       // the graph as parsed, instances expanded (its parameters are the tests' reference)
  nlohmann::json stats;       // the --stats file (nodes, reports)
  std::string error;          // why the command failed; empty when it succeeded
  bool ok() const { return error.empty(); }
};

// Runs `orogen eval graphs/<file> --resolution <resolution> -o <scratch> --stats ...`. A failed command leaves
// `error` set and `out` empty rather than failing the caller: called from SetUpTestSuite, a failure there makes
// googletest mark every test of the suite "[  SKIPPED ]", which ctest counts as skipped, not failed. Each test
// asserts `ok()` instead.
SeedRun run_seed_graph(const std::string& file, const std::string& resolution);

// The parameters of node `id` in a parsed graph (throws if absent).
const nlohmann::json& node_params(const nlohmann::json& graph, const std::string& id);

// One channel of a float image file, top (north) row first.
struct Raster {
  int width = 0, height = 0;
  std::vector<double> v;
  double at(int i, int j) const { return v[static_cast<std::size_t>(j) * width + i]; }
};
Raster read_raster(const std::filesystem::path& path, int channel = 0);
// The channel named `name` (EXR stores channels sorted by name, so monthly images need the name).
Raster read_raster(const std::filesystem::path& path, const std::string& name);

// A CSV file with a header line: column name -> values (numbers).
std::map<std::string, std::vector<double>> read_csv(const std::filesystem::path& path);

}  // namespace orogen::test
