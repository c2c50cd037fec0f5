// The memory estimate behind --max-memory covers what a node needs beyond its outputs' samples: a band of a
// file streamed onto the domain (its header tells the band's size), an image of many channels, a word grown by
// rewriting, a scene serialized in memory. Each case would be accepted by the default estimate (outputs by type at the
// domain) and is refused by the node's own declaration, before the node allocates.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "evaluator/memory_estimate.h"
#include "graph/cost_query.h"
#include "graph/graph.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/registry.h"
#include "graph/scene.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/plants/lsystem.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;
using test::cli_binary;
using test::run_process;
using test::scratch_dir;
using test::write_text;

const NodeType& type_of(const char* name) {
  const NodeType* t = NodeRegistry::instance().find(name);
  if (!t) throw std::runtime_error(std::string("no node type ") + name);
  return *t;
}

// The estimate for `type` at `domain` with its default parameters changed by `set`, and these inputs (null:
// before they exist, every input linked).
template <class Set>
std::uint64_t estimate(const NodeType& type, const Domain& domain, Set set, const std::vector<PortValue>* inputs,
                       std::vector<bool> linked = {}) {
  Graph g;
  Node& n = g.add_node(type.name, "n");
  set(n.params);
  const std::vector<ParamValue> params = g.effective_params(n);
  return estimate_node_bytes(CostQuery{type, domain, ParamView(type, params), inputs, {}, std::move(linked)});
}

const auto kDefaults = [](std::map<std::string, ParamValue>&) {};

// A 16-bit PNG of `side`^2 constant pixels: a few kilobytes on disk for any side.
fs::path constant_png(const fs::path& dir, int side) {
  Heightfield h(Domain::from_extent({0, 0}, {1, 1}, {side, side}));
  for (float& v : h.data) v = 100.0f;
  HeightfieldWriteOptions o;
  o.format = HeightFormat::Png16;
  o.range = HeightRange{0.0, 1000.0};
  o.compression_level = 9;
  const fs::path path = dir / ("flat" + std::to_string(side) + ".png");
  write_heightfield_file(h, path, o);
  return path;
}

TEST(MemoryEstimate, ReadHeightfieldCountsABandOfTheFileFromItsHeader) {
  const fs::path dir = scratch_dir("estimate-read");
  const fs::path png = constant_png(dir, 2048);
  EXPECT_LT(fs::file_size(png), 200u * 1024u) << "the file must be small on disk for the case to mean anything";
  const HeightRasterShape shape = probe_height_raster(png);
  EXPECT_EQ(shape.width, 2048);
  EXPECT_EQ(shape.height, 2048);
  EXPECT_EQ(shape.channels, 1);
  EXPECT_EQ(shape.bytes_per_value, 2u);
  EXPECT_EQ(shape.band_rows, 16);
  // Read whole (read_height_raster): the stored channel, its doubles and the float field on the image's lattice.
  EXPECT_EQ(height_raster_read_bytes(shape), 2048ull * 2048ull * (2 + 8 + 4));
  // Streamed onto a domain (the node): a band of 16 rows as decoded and as kept, a row of doubles, two of floats.
  EXPECT_EQ(height_stream_read_bytes(shape), 16ull * 2048 * 2 * 2 + 2048ull * (8 + 2 * 4));

  const NodeType& read = type_of("ReadHeightfield");
  const Domain small = Domain::from_extent({0, 0}, {100, 100}, {16, 16});
  const auto with_path = [&](std::map<std::string, ParamValue>& p) { p["path"] = png.string(); };
  EXPECT_EQ(estimate(read, small, with_path, nullptr),
            estimate_output_bytes(read, small) + height_stream_read_bytes(shape));
  EXPECT_LT(estimate(read, small, kDefaults, nullptr), 16u * 16u * 16u) << "no file: the outputs only";
  // A file that cannot be read adds nothing: the node says what is wrong when it runs.
  const auto missing = [&](std::map<std::string, ParamValue>& p) { p["path"] = (dir / "missing.png").string(); };
  EXPECT_EQ(estimate(read, small, missing, nullptr), estimate_output_bytes(read, small));

  // End to end: a file of 4 M pixels onto 16 x 16 samples is accepted under a limit far below the pixels' bytes
  // (read whole, it held 58 MB).
  write_text(dir / "g.json", R"({ "format": "orogen-graph", "version": 6,
    "domain": { "size": [100, 100], "resolution": [16, 16] },
    "nodes": [ { "id": "read", "type": "ReadHeightfield", "params": { "path": "flat2048.png" } },
               { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "read.out" },
                 "params": { "path": "h.exr" } } ] })");
  const auto accepted = run_process(
      cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q", "--max-memory", "4M"});
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "h.exr"));
}

TEST(MemoryEstimate, ResourceStackCountsEveryChannelOfItsInputs) {
  const NodeType& stack = type_of("ResourceStack");
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {64, 64});
  const std::uint64_t samples = 64 * 64;
  const std::uint64_t outputs = estimate_output_bytes(stack, d);
  // Before the inputs exist: twelve monthly channels per linked group.
  EXPECT_EQ(estimate(stack, d, kDefaults, nullptr), outputs + samples * (37 - 4) * 4);
  EXPECT_EQ(estimate(stack, d, kDefaults, nullptr, {true, true, false, false}), outputs + samples * (13 - 4) * 4);
  EXPECT_EQ(estimate(stack, d, kDefaults, nullptr, {true, false, false, false}), outputs);
  // With the inputs: their real channel counts.
  std::vector<PortValue> inputs(stack.inputs.size());
  inputs[static_cast<std::size_t>(stack.input_index("in"))] = std::make_shared<const Heightfield>(d);
  inputs[static_cast<std::size_t>(stack.input_index("temperature"))] = std::make_shared<const Image>(d, 12);
  inputs[static_cast<std::size_t>(stack.input_index("humidity"))] = std::make_shared<const Image>(d, 5);
  EXPECT_EQ(estimate(stack, d, kDefaults, &inputs), outputs + samples * (18 - 4) * 4);
}

TEST(MemoryEstimate, LSystemBoundsTheWordByMaxModulesAndTheWidestModule) {
  // A rule that doubles a 16-parameter module every step: 2^10 modules after 10 steps.
  const std::string params = "a,b,c,d,e,f,g,h,i,j,k,l,m,n,o,p";
  const std::string axiom = "A(1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16)";
  const std::string rules = "A(" + params + ") -> A(" + params + ")A(" + params + ")";
  const plants::LSystem l(axiom, rules);
  EXPECT_EQ(l.max_module_parameters(), 16u);
  plants::DeriveOptions o;
  o.iterations = 10;
  o.max_modules = 1024;
  const ModuleString word = l.derive(o);
  ASSERT_EQ(word.size(), 1024u);
  // The bound holds the word it bounds, and not absurdly more.
  const std::uint64_t bound = plants::derive_peak_bytes(1024, l.max_module_parameters());
  EXPECT_GE(bound, word.byte_size());
  EXPECT_LE(bound, 8 * word.byte_size());

  const NodeType& lsystem = type_of("LSystem");
  const Domain d = Domain::from_extent({0, 0}, {1, 1}, {2, 2});
  const auto wide = [&](std::map<std::string, ParamValue>& p) {
    p["axiom"] = axiom;
    p["rules"] = rules;
    p["max_modules"] = std::int64_t{100000000};
    p["iterations"] = std::int64_t{40};
  };
  EXPECT_GE(estimate(lsystem, d, wide, nullptr), 100000000ull * (1 + 4 + 16 * 4));
  // Ten doublings: 1024 modules, whatever max_modules allows.
  const auto ten = [&](std::map<std::string, ParamValue>& p) {
    wide(p);
    p["iterations"] = std::int64_t{10};
  };
  EXPECT_EQ(estimate(lsystem, d, ten, nullptr), plants::derive_peak_bytes(1024, 16));
  EXPECT_EQ(l.max_word_length(10, 1u << 30), 1024u);
  // Algae (A -> AB; B -> A) grows by Fibonacci numbers: 13 modules after 5 steps, exactly.
  EXPECT_EQ(plants::LSystem("A", "A -> AB; B -> A").max_word_length(5, 1000), 13u);
  EXPECT_EQ(plants::derive_text("A", "A -> AB; B -> A", 5).size(), 13u);
  // A condition may fail and keep the module: the bound counts it kept as well as rewritten.
  EXPECT_EQ(plants::LSystem("A(1)", "A(x) : x < 3 -> A(x+1)A(x+1)").max_word_length(3, 1000), 8u);
  EXPECT_EQ(plants::LSystem("B", "A -> AA").max_word_length(30, 1000), 1u) << "no rule for B";
  const auto narrow = [&](std::map<std::string, ParamValue>& p) {
    p["axiom"] = std::string("A");
    p["rules"] = std::string("A -> AB; B -> A");
    p["max_modules"] = std::int64_t{100000000};
  };
  EXPECT_LT(estimate(lsystem, d, narrow, nullptr), estimate(lsystem, d, wide, nullptr) / 10);

  // End to end: 24 doublings of a 16-parameter module are refused before the first step.
  const fs::path dir = scratch_dir("estimate-lsystem");
  nlohmann::json g = {
      {"format", "orogen-graph"},
      {"version", 6},
      {"domain", {{"size", {10, 10}}, {"resolution", {4, 4}}}},
      {"nodes",
       {{{"id", "grow"},
         {"type", "LSystem"},
         {"params", {{"axiom", axiom}, {"rules", rules}, {"iterations", 24}, {"max_modules", 100000000}}}},
        {{"id", "turtle"}, {"type", "Turtle3D"}, {"inputs", {{"in", "grow.out"}}}}}}};
  write_text(dir / "g.json", g.dump(2));
  const auto r = run_process(
      cli_binary(), {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q", "--max-memory", "256M"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("node 'grow'"), std::string::npos) << r.err;
}

TEST(MemoryEstimate, WriteSceneCountsItsInstancesOnceTheSceneExists) {
  const NodeType& write = type_of("WriteScene");
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {16, 16});
  auto points = std::make_shared<Points>();
  for (int k = 0; k < 100000; ++k) points->add(glm::vec3(static_cast<float>(k % 100), static_cast<float>(k / 100), 0));
  auto scene = std::make_shared<Scene>();
  scene->instances = points;
  std::vector<PortValue> inputs(write.inputs.size());
  inputs[static_cast<std::size_t>(write.input_index("in"))] = ScenePtr(scene);
  const auto nodes = [](std::map<std::string, ParamValue>& p) { p["instancing"] = std::string("nodes"); };
  const std::uint64_t outputs = estimate_output_bytes(write, d);
  EXPECT_GE(estimate(write, d, nodes, &inputs), outputs + 100000ull * 1024);
  EXPECT_GT(estimate(write, d, nodes, &inputs), estimate(write, d, kDefaults, &inputs));
  EXPECT_GT(estimate(write, d, kDefaults, &inputs), outputs);
  EXPECT_EQ(estimate(write, d, nodes, nullptr), outputs) << "before the scene exists nothing is known";
}

}  // namespace
}  // namespace orogen
