// The graph file format: exact round trips, canonical text, atomic saving, migrations, and one clear
// diagnostic (message, JSON path, node id) for each kind of malformed file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include <sys/resource.h>

#include <nlohmann/json.hpp>

#include "graph/exec_context.h"
#include "graph/graph_file.h"
#include "graph/registry.h"
#include "nodes/common/hash.h"
#include "support/test_paths.h"

namespace orogen {

// Test node types of this file: ports of several types, optional inputs, and a parameter of every type.
OROGEN_NODE(TestSource) {
  b.category("test").description("Source with one parameter of every type.");
  b.output("height", PortType::Heightfield).description("A field");
  b.output("color", PortType::Image).description("An image");
  b.output("points", PortType::Points).description("Points");
  b.param_float("scale", 1.0).range(0.0, 100.0).unit(Unit::Metre).description("A length");
  b.param_int("octaves", 4).unit(Unit::Count).range(1, 16).description("A count");
  b.param_bool("enabled", true).description("A switch");
  b.param_vec2("offset", {0.0, 0.0}).range(-1e4, 1e4).unit(Unit::Metre).description("A shift");
  b.param_vec3("direction", {0.0, 0.0, 1.0}).unit(Unit::Unitless).description("A direction");
  b.param_color("tint", {1.0f, 1.0f, 1.0f, 1.0f}).description("A color");
  b.param_enum("basis", {"perlin", "value", "simplex"}, "perlin").description("A choice");
  b.param_string("label", "").description("A name");
  b.param_path("file", "out.exr").extensions({".exr", ".png"}).description("A file");
  b.param_seed("seed", 0).description("A seed");
  b.param_curve("remap", CurveValue::identity()).description("A curve");
  b.param_gradient("palette", GradientValue{{{0.0, {0, 0, 0, 1}}, {1.0, {1, 1, 1, 1}}}}).description("A gradient");
  b.execute([](ExecContext&) {});
}

OROGEN_NODE(TestFilter) {
  b.category("test").description("A filter with a required and two optional inputs.");
  b.input("height", PortType::Heightfield).description("Field to filter");
  b.input("mask", PortType::Heightfield).optional().description("Where to filter");
  b.input("points", PortType::Points).optional().description("Points");
  b.output("out", PortType::Heightfield).description("Filtered field");
  b.param_float("strength", 0.5).unit(Unit::Unitless).range(0.0, 1.0).description("How much");
  b.execute([](ExecContext&) {});
}

OROGEN_NODE(TestPaint) {
  b.category("test").description("Takes an image, has no parameters.");
  b.input("image", PortType::Image).description("Image");
  b.input("curves", PortType::Curves).optional().description("Curves");
  b.output("out", PortType::Image).description("Painted image");
  b.execute([](ExecContext&) {});
}

namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// A graph that uses every parameter type with non-default values, links and editor positions.
Graph full_graph() {
  Graph g;
  g.domain.origin = {-512.25, 1000.0};
  g.domain.size = {4096.0, 2048.5};
  g.domain.resolution = {1025, 513};
  g.add_node("TestSource", "src");
  g.set_param("src", "scale", 0.1);
  g.set_param("src", "octaves", std::int64_t{7});
  g.set_param("src", "enabled", false);
  g.set_param("src", "offset", glm::dvec2(1.0 / 3.0, -2.5e-7));
  g.set_param("src", "direction", glm::dvec3(0.6, -0.8, 1e-300));
  g.set_param("src", "tint", glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
  g.set_param("src", "basis", std::string("simplex"));
  g.set_param("src", "label", std::string("quote \" slash \\ tab \t unicode \xC3\xA9"));
  g.set_param("src", "file", std::string("maps/height.png"));
  g.set_param("src", "seed", std::numeric_limits<std::uint64_t>::max());
  g.set_param("src", "remap", CurveValue{{{0.0, 0.0}, {0.25, 0.7}, {1.0, 1.0}}});
  g.set_param("src", "palette",
              GradientValue{{{0.0, {0.0f, 0.1f, 0.2f, 1.0f}}, {0.4, {0.9f, 0.8f, 0.7f, 0.6f}}, {1.0, {1, 1, 1, 1}}}});
  g.add_node("TestFilter", "smooth");
  g.connect({"src", "height"}, "smooth", "height");
  g.connect({"src", "points"}, "smooth", "points");
  g.set_param("smooth", "strength", 0.75);
  g.add_node("TestPaint", "paint");
  g.connect({"src", "color"}, "paint", "image");
  g.editor.positions["src"] = {0.0, -120.5};
  g.editor.positions["paint"] = {1e-3, 3.0e8};
  return g;
}

LoadResult parse_ok(const std::string& text, const LoadOptions& options = {}) {
  auto r = parse_graph(text, options);
  EXPECT_TRUE(r.ok()) << r.error_text();
  return r;
}

TEST(GraphFile, RoundTripKeepsEveryParameterTypeLinksAndPositions) {
  const Graph g = full_graph();
  const std::string text = serialize_graph(g);
  const auto loaded = parse_ok(text);
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(*loaded.graph == g);
  EXPECT_EQ(serialize_graph(*loaded.graph), text);
  // Spot checks that equality is not vacuous.
  EXPECT_EQ(std::get<std::uint64_t>(loaded.graph->param("src", "seed")), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(std::get<glm::vec4>(loaded.graph->param("src", "tint")), glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
  EXPECT_EQ(loaded.graph->at("paint").inputs.at("image"), (PortRef{"src", "color"}));
  EXPECT_EQ(loaded.graph->editor.positions.at("paint"), glm::dvec2(1e-3, 3.0e8));
}

TEST(GraphFile, CanonicalTextIsReproducedExactly) {
  // What serialize_graph writes: this is the documented look of a file.
  const std::string text = R"({
  "format": "orogen-graph",
  "version": 7,
  "domain": {
    "size": [4096, 2048.5],
    "resolution": [1025, 513],
    "origin": [-512.25, 1000]
  },
  "nodes": [
    {
      "id": "src",
      "type": "TestSource",
      "params": {
        "scale": 0.1,
        "octaves": 7,
        "enabled": false,
        "offset": [0.3333333333333333, -2.5e-07],
        "direction": [0.6, -0.8, 1e-300],
        "tint": [0.1, 0.2, 0.3, 0.5],
        "basis": "simplex",
        "label": "quote \" slash \\ tab \t unicode é",
        "file": "maps/height.png",
        "seed": 18446744073709551615,
        "remap": [
          [0, 0],
          [0.25, 0.7],
          [1, 1]
        ],
        "palette": [
          [0, [0, 0.1, 0.2, 1]],
          [0.4, [0.9, 0.8, 0.7, 0.6]],
          [1, [1, 1, 1, 1]]
        ]
      }
    },
    {
      "id": "smooth",
      "type": "TestFilter",
      "params": {
        "strength": 0.75
      },
      "inputs": {
        "height": "src.height",
        "points": "src.points"
      }
    },
    {
      "id": "paint",
      "type": "TestPaint",
      "inputs": {
        "image": "src.color"
      }
    }
  ],
  "editor": {
    "positions": {
      "src": [0, -120.5],
      "paint": [0.001, 3e+08]
    }
  }
}
)";
  const auto loaded = parse_ok(text);
  ASSERT_TRUE(loaded.ok());
  EXPECT_EQ(serialize_graph(*loaded.graph), text);
  EXPECT_TRUE(*loaded.graph == full_graph());
}

TEST(GraphFile, WritesOnlyExplicitParametersInDeclarationOrderAndOmitsEmptySections) {
  Graph g;
  g.add_node("TestSource", "a");
  g.set_param("a", "seed", std::uint64_t{3});  // declared last of the two
  g.set_param("a", "scale", 2.0);              // declared first
  g.add_node("TestPaint", "p");
  const std::string text = serialize_graph(g);
  EXPECT_LT(text.find("\"scale\""), text.find("\"seed\""));
  EXPECT_EQ(text.find("\"octaves\""), std::string::npos);  // default: not written
  EXPECT_EQ(text.find("\"editor\""), std::string::npos);
  EXPECT_EQ(text.find("\"origin\""), std::string::npos);
  EXPECT_EQ(text.find("\"inputs\""), std::string::npos);
  // The TestPaint node has neither params nor inputs: just id and type.
  EXPECT_THAT(text, HasSubstr("{\n      \"id\": \"p\",\n      \"type\": \"TestPaint\"\n    }"));
  // Resetting a parameter removes it from the file.
  g.reset_param("a", "scale");
  EXPECT_EQ(serialize_graph(g).find("\"scale\""), std::string::npos);
}

TEST(GraphFile, EmptyGraphRoundTrips) {
  const Graph g;
  const std::string text = serialize_graph(g);
  EXPECT_EQ(text, "{\n  \"format\": \"orogen-graph\",\n  \"version\": " + std::to_string(kGraphFormatVersion) +
                      ",\n  \"domain\": {\n    \"size\": [1024, 1024],\n"
                      "    \"resolution\": [256, 256]\n  },\n  \"nodes\": []\n}\n");
  const auto loaded = parse_ok(text);
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(*loaded.graph == g);
}

TEST(GraphFile, FloatsRoundTripBitExactly) {
  // Doubles and float32 colours from raw bit patterns over the whole exponent range.
  std::uint64_t state = kGoldenGamma;
  auto next = [&] {
    state += kGoldenGamma;
    return mix64(state);
  };
  auto random_double = [&] {
    for (;;) {
      std::uint64_t bits = next();
      double d;
      std::memcpy(&d, &bits, sizeof d);
      if (std::isfinite(d)) return d;
    }
  };
  auto random_float = [&] {
    for (;;) {
      auto bits = static_cast<std::uint32_t>(next());
      float f;
      std::memcpy(&f, &bits, sizeof f);
      if (std::isfinite(f)) return f;
    }
  };
  for (int round = 0; round < 200; ++round) {
    Graph g;
    g.add_node("TestSource", "s");
    g.set_param("s", "direction", glm::dvec3(random_double(), random_double(), random_double()));
    g.set_param("s", "tint", glm::vec4(random_float(), random_float(), random_float(), random_float()));
    std::vector<double> xs{random_double(), random_double(), random_double(), random_double()};
    std::sort(xs.begin(), xs.end());
    CurveValue curve;
    for (double x : xs) curve.points.emplace_back(x, random_double());
    if (std::adjacent_find(xs.begin(), xs.end()) == xs.end()) g.set_param("s", "remap", curve);
    g.editor.positions["s"] = {random_double(), random_double()};
    const auto text = serialize_graph(g);
    const auto loaded = parse_graph(text);
    ASSERT_TRUE(loaded.ok()) << loaded.error_text() << text;
    const auto& a = std::get<glm::dvec3>(g.param("s", "direction"));
    const auto& b = std::get<glm::dvec3>(loaded.graph->param("s", "direction"));
    const auto& ca = std::get<glm::vec4>(g.param("s", "tint"));
    const auto& cb = std::get<glm::vec4>(loaded.graph->param("s", "tint"));
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << text;
    EXPECT_EQ(std::memcmp(&ca, &cb, sizeof ca), 0) << text;
    EXPECT_TRUE(*loaded.graph == g) << text;
  }
}

TEST(GraphFile, MinusZeroKeepsItsSign) {
  Graph g;
  g.add_node("TestSource", "s");
  g.set_param("s", "offset", glm::dvec2(-0.0, 0.0));
  const auto loaded = parse_ok(serialize_graph(g));
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(std::signbit(std::get<glm::dvec2>(loaded.graph->param("s", "offset")).x));
}

TEST(GraphFile, AcceptsIntegersForFloatsAndThreeComponentColours) {
  const auto r = parse_ok(R"({"format": "orogen-graph", "version": 1, "nodes": [
    {"id": "s", "type": "TestSource", "params": {"scale": 3, "tint": [1, 0.5, 0],
     "palette": [[0, [1, 0, 0]], [1, [0, 0, 1, 0.5]]]}}]})");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(std::get<double>(r.graph->param("s", "scale")), 3.0);
  EXPECT_EQ(std::get<glm::vec4>(r.graph->param("s", "tint")), glm::vec4(1.0f, 0.5f, 0.0f, 1.0f));
  const auto& palette = std::get<GradientValue>(r.graph->param("s", "palette"));
  ASSERT_EQ(palette.stops.size(), 2u);
  EXPECT_EQ(palette.stops[0].color, glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(palette.stops[1].color, glm::vec4(0, 0, 1, 0.5f));
  // The domain is optional.
  EXPECT_TRUE(r.graph->domain == GraphDomain{});
}

TEST(GraphFile, SaveWritesTheSerializedTextAndLoadReadsItBack) {
  const auto dir = test::scratch_dir("graph-file-save");
  const auto path = dir / "sub" / "graph.json";
  const Graph g = full_graph();
  save_graph_file(g, path);
  std::ifstream in(path, std::ios::binary);
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str(), serialize_graph(g));
  const auto loaded = load_graph_file(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error_text();
  EXPECT_TRUE(*loaded.graph == g);
}

TEST(GraphFile, FailedSaveLeavesThePreviousFileIntact) {
  const auto dir = test::scratch_dir("graph-file-atomic");
  const auto path = dir / "graph.json";
  const std::string old_text = "previous contents\n";
  { std::ofstream(path, std::ios::binary) << old_text; }
  // Make the write fail part-way: a file-size limit below the new file's size (EFBIG instead of SIGXFSZ).
  const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit limited = saved;
  limited.rlim_cur = 64;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  bool threw = false;
  try {
    save_graph_file(full_graph(), path);
  } catch (const std::runtime_error&) {
    threw = true;
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_TRUE(threw);
  std::ifstream in(path, std::ios::binary);
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str(), old_text);
  // No temporary file is left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(GraphFile, LoadingAMissingFileSaysSo) {
  const auto r = load_graph_file(test::scratch_dir("graph-file-missing") / "nope.json");
  ASSERT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_THAT(r.diagnostics[0].message, StartsWith("cannot open "));
  EXPECT_THAT(r.diagnostics[0].message, HasSubstr("nope.json: No such file or directory"));
}

// Version 0 of the format (a test-only history): nodes were under "node_list" and parameters under "settings".
TEST(GraphFile, OlderVersionsAreMigrated) {
  register_graph_migration(0, [](nlohmann::json& file) {
    file["nodes"] = file["node_list"];
    file.erase("node_list");
    for (auto& node : file["nodes"]) {
      if (node.contains("settings")) {
        node["params"] = node["settings"];
        node.erase("settings");
      }
    }
  });
  const auto r = parse_ok(R"({"format": "orogen-graph", "version": 0,
    "node_list": [{"id": "s", "type": "TestSource", "settings": {"octaves": 9}}]})");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(std::get<std::int64_t>(r.graph->param("s", "octaves")), 9);
  // Saving writes the current version.
  EXPECT_THAT(serialize_graph(*r.graph), HasSubstr("\"version\": " + std::to_string(kGraphFormatVersion) + ","));

  // Problems in a migrated file are still reported, with paths in the migrated document.
  const auto bad = parse_graph(R"({"format": "orogen-graph", "version": 0,
    "node_list": [{"id": "s", "type": "TestSource", "settings": {"octaves": 99}}]})");
  ASSERT_EQ(bad.diagnostics.size(), 1u);
  EXPECT_EQ(bad.diagnostics[0].path, "/nodes/0/params/octaves");
}

TEST(GraphFile, MissingOrFailingMigrationIsAnError) {
  const auto missing = parse_graph(R"({"format": "orogen-graph", "version": -5, "nodes": []})");
  ASSERT_EQ(missing.diagnostics.size(), 1u);
  EXPECT_EQ(missing.diagnostics[0].path, "/version");
  EXPECT_EQ(missing.diagnostics[0].message,
            "cannot read format version -5: no migration from version -5 to -4 is known");

  register_graph_migration(-1, [](nlohmann::json&) { throw std::runtime_error("no such field"); });
  const auto failing = parse_graph(R"({"format": "orogen-graph", "version": -1, "nodes": []})");
  ASSERT_EQ(failing.diagnostics.size(), 1u);
  EXPECT_EQ(failing.diagnostics[0].message, "migrating the file from format version -1 to 0 failed: no such field");
}

TEST(GraphFile, DanglingLinksAreDroppedOnlyWhenAsked) {
  const std::string fragment = R"({"format": "orogen-graph", "version": 1, "nodes": [
    {"id": "f", "type": "TestFilter", "inputs": {"height": "elsewhere.out", "points": "elsewhere.points"}}]})";
  const auto strict = parse_graph(fragment);
  ASSERT_EQ(strict.diagnostics.size(), 2u) << strict.error_text();
  EXPECT_EQ(strict.diagnostics[0].message, "link to missing node 'elsewhere'");

  LoadOptions paste;
  paste.drop_dangling_links = true;
  const auto pasted = parse_ok(fragment, paste);
  ASSERT_TRUE(pasted.ok());
  EXPECT_TRUE(pasted.graph->at("f").inputs.empty());
}

TEST(GraphFile, UnconnectedRequiredInputsCanBeAllowed) {
  const std::string text = R"({"format": "orogen-graph", "version": 1, "nodes": [{"id": "f", "type": "TestFilter"}]})";
  EXPECT_FALSE(parse_graph(text).ok());
  LoadOptions options;
  options.allow_unconnected_inputs = true;
  EXPECT_TRUE(parse_ok(text, options).ok());
}

TEST(GraphFile, DiagnosticText) {
  EXPECT_EQ((Diagnostic{"/nodes/2/params/octaves", "base", "too many"}).str(),
            "/nodes/2/params/octaves [node 'base']: too many");
  EXPECT_EQ((Diagnostic{"/format", "", "wrong"}).str(), "/format: wrong");
  EXPECT_EQ((Diagnostic{"", "", "malformed"}).str(), "malformed");
  const auto r = parse_graph(R"({"format": "x", "version": 1, "nodes": [], "extra": 1})");
  EXPECT_EQ(
      r.error_text(),
      "/format: \"format\" must be \"orogen-graph\", found the string \"x\"\n"
      "/extra: unknown field 'extra' in the file (expected one of: format, version, domain, interface, subgraphs, "
      "nodes, "
      "node_libraries, editor)\n");
}

// Damaged files (characters deleted, inserted or replaced at random) never crash the loader: each gives a
// graph that saves and reloads to itself, or diagnostics that all say something.
TEST(GraphFile, RandomlyDamagedFilesAreEitherValidOrDiagnosed) {
  const std::string original = serialize_graph(full_graph());
  const std::string alphabet = "{}[],:\".0123456789-eE \n\\abcxyz_";
  std::uint64_t state = 77;
  auto rnd = [&](std::size_t n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::size_t>((state >> 33) % n);
  };
  int valid = 0, invalid = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    std::string text = original;
    const int edits = 1 + static_cast<int>(rnd(3));
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rnd(text.size());
      switch (rnd(3)) {
        case 0:
          text.erase(at, 1);
          break;
        case 1:
          text.insert(at, 1, alphabet[rnd(alphabet.size())]);
          break;
        default:
          text[at] = alphabet[rnd(alphabet.size())];
          break;
      }
    }
    const auto r = parse_graph(text);
    if (r.ok()) {
      ++valid;
      EXPECT_TRUE(r.diagnostics.empty());
      const auto again = parse_graph(serialize_graph(*r.graph));
      ASSERT_TRUE(again.ok()) << again.error_text() << "\nfrom:\n" << text;
      EXPECT_TRUE(*again.graph == *r.graph) << text;
    } else {
      ++invalid;
      ASSERT_FALSE(r.diagnostics.empty()) << text;
      for (const auto& d : r.diagnostics) EXPECT_FALSE(d.message.empty()) << text;
    }
  }
  // Both outcomes occur (whitespace and digit edits often leave a valid file).
  EXPECT_GT(valid, 20);
  EXPECT_GT(invalid, 500);
}

// ---- Parameter values from JSON and from command-line text ----

const ParamDecl& decl_of(const char* type, const char* name) {
  return *NodeRegistry::instance().find(type)->find_param(name);
}

TEST(ParamJson, FromTextParsesJsonOrTakesBareStrings) {
  std::string error;
  auto v = param_from_text("2.5", decl_of("TestSource", "scale"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<double>(*v), 2.5);
  v = param_from_text("simplex", decl_of("TestSource", "basis"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::string>(*v), "simplex");
  v = param_from_text("\"value\"", decl_of("TestSource", "basis"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::string>(*v), "value");
  v = param_from_text("123", decl_of("TestSource", "label"), error);  // a string parameter takes the text
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::string>(*v), "123");
  v = param_from_text("out/h.png", decl_of("TestSource", "file"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::string>(*v), "out/h.png");
  v = param_from_text("[1, -2]", decl_of("TestSource", "offset"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<glm::dvec2>(*v), glm::dvec2(1, -2));
  v = param_from_text("18446744073709551615", decl_of("TestSource", "seed"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::uint64_t>(*v), std::numeric_limits<std::uint64_t>::max());
  v = param_from_text("false", decl_of("TestSource", "enabled"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_FALSE(std::get<bool>(*v));
  v = param_from_text("[[0, 0], [0.5, 0.2], [1, 1]]", decl_of("TestSource", "remap"), error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<CurveValue>(*v).points.size(), 3u);

  EXPECT_FALSE(param_from_text("abc", decl_of("TestSource", "scale"), error));
  EXPECT_EQ(error, "expected a number, found the string \"abc\"");
  EXPECT_FALSE(param_from_text("1e400", decl_of("TestSource", "scale"), error));
  EXPECT_EQ(error, "expected a number, found the string \"1e400\"");
  EXPECT_FALSE(param_from_text("500", decl_of("TestSource", "scale"), error));
  EXPECT_EQ(error, "value 500 is above the maximum 100");
  EXPECT_FALSE(param_from_text("2.5", decl_of("TestSource", "octaves"), error));
  EXPECT_EQ(error, "expected an integer, found the number 2.5");
  EXPECT_FALSE(param_from_text("perlin2", decl_of("TestSource", "basis"), error));
  EXPECT_EQ(error, "'perlin2' is not one of: perlin, value, simplex (did you mean 'perlin'?)");
  EXPECT_FALSE(param_from_text("h.tif", decl_of("TestSource", "file"), error));
  EXPECT_EQ(error, "file extension must be one of: .exr, .png");
}

TEST(ParamJson, IntegerLimits) {
  std::string error;
  const ParamDecl& seed = decl_of("TestSource", "seed");
  EXPECT_FALSE(param_from_json(nlohmann::json(-1), seed, error));
  EXPECT_EQ(error, "a seed must not be negative, found -1");
  EXPECT_FALSE(param_from_json(nlohmann::json(1.5), seed, error));
  EXPECT_EQ(error, "expected a seed (an integer from 0 to 18446744073709551615), found the number 1.5");
  ParamDecl wide;
  wide.name = "n";
  wide.type = ParamType::Int;
  EXPECT_FALSE(param_from_json(nlohmann::json(std::uint64_t{1} << 63), wide, error));
  EXPECT_EQ(error, "the integer 9223372036854775808 is too large");
  auto v = param_from_json(nlohmann::json(std::numeric_limits<std::int64_t>::min()), wide, error);
  ASSERT_TRUE(v) << error;
  EXPECT_EQ(std::get<std::int64_t>(*v), std::numeric_limits<std::int64_t>::min());
}

TEST(ParamJson, ToJsonWritesTheDocumentedEncodings) {
  EXPECT_EQ(param_to_json(ParamValue(2.5)).dump(), "2.5");
  EXPECT_EQ(param_to_json(ParamValue(std::int64_t{-3})).dump(), "-3");
  EXPECT_EQ(param_to_json(ParamValue(true)).dump(), "true");
  EXPECT_EQ(param_to_json(ParamValue(glm::dvec2(1, 2))).dump(), "[1.0,2.0]");
  EXPECT_EQ(param_to_json(ParamValue(glm::dvec3(1, 2, 3))).dump(), "[1.0,2.0,3.0]");
  EXPECT_EQ(param_to_json(ParamValue(glm::vec4(0.5f, 0.25f, 1.0f, 1.0f))).dump(), "[0.5,0.25,1.0,1.0]");
  EXPECT_EQ(param_to_json(ParamValue(std::string("x"))).dump(), "\"x\"");
  EXPECT_EQ(param_to_json(ParamValue(std::uint64_t{7})).dump(), "7");
  EXPECT_EQ(param_to_json(ParamValue(CurveValue{{{0, 1}, {2, 3}}})).dump(), "[[0.0,1.0],[2.0,3.0]]");
  EXPECT_EQ(param_to_json(ParamValue(GradientValue{{{0.5, {1, 0, 0, 1}}}})).dump(), "[[0.5,[1.0,0.0,0.0,1.0]]]");
}

// ---- Malformed files: each gives exactly one diagnostic, with its own message, path and node id ----

struct Malformed {
  const char* name;
  std::string text;
  std::string path;
  std::string node;
  std::string message;  // exact, or a prefix when `prefix_only`
  bool prefix_only = false;
};

std::string with_nodes(const std::string& nodes, const std::string& extra = "") {
  return R"({"format": "orogen-graph", "version": 1, "nodes": [)" + nodes + "]" + extra + "}";
}

const std::string kSrc = R"({"id": "src", "type": "TestSource"})";

std::string filter(const std::string& inputs) {
  return R"({"id": "f", "type": "TestFilter", "inputs": {)" + inputs + "}}";
}

std::vector<Malformed> malformed_cases() {
  return {
      {"SyntaxError", "{\n  \"format\": \"orogen-graph\",\n  \"version\": 1\n  \"nodes\": []\n}", "", "",
       "malformed JSON at line 4, column 9: syntax error while parsing object - unexpected string literal; expected "
       "'}'"},
      {"NumberOverflow", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"scale": 1e400}})"),
       "/nodes/0/params/scale", "", "malformed JSON at line 1, column 112: number overflow parsing '1e400'"},
      {"DuplicateKey", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"scale": 1, "scale": 2}})"),
       "/nodes/0/params/scale", "src", "duplicate key 'scale': each key may appear only once in an object"},
      {"NotAnObject", "[1, 2]", "", "",
       "a graph file must be a JSON object {\"format\": \"orogen-graph\", ...}, found an array of 2 elements"},
      {"MissingFormat", R"({"version": 1, "nodes": []})", "/format", "",
       "missing \"format\": \"orogen-graph\" (is this an Orogen graph file?)"},
      {"WrongFormat", R"({"format": "gaea-graph", "version": 1, "nodes": []})", "/format", "",
       "\"format\" must be \"orogen-graph\", found the string \"gaea-graph\""},
      {"MissingVersion", R"({"format": "orogen-graph", "nodes": []})", "/version", "",
       "missing \"version\": the format version (this build writes 7)"},
      {"VersionNotInteger", R"({"format": "orogen-graph", "version": 1.0, "nodes": []})", "/version", "",
       "\"version\" must be an integer, found the number 1.0"},
      {"NewerVersion", R"({"format": "orogen-graph", "version": 8, "nodes": [{"bad": 1}], "future": true})", "/version",
       "", "this file was written by a newer Orogen (version 8, this build reads up to 7); update Orogen to open it"},
      {"UnknownTopLevelField", with_nodes("", R"(, "editr": {})"), "/editr", "",
       "unknown field 'editr' in the file (did you mean 'editor'?)"},
      {"MissingNodes", R"({"format": "orogen-graph", "version": 1})", "/nodes", "",
       "missing \"nodes\": the list of nodes (may be empty: [])"},
      {"NodesNotArray", R"({"format": "orogen-graph", "version": 1, "nodes": {}})", "/nodes", "",
       "\"nodes\" must be an array of nodes, found an object"},
      {"UnknownDomainField", with_nodes("", R"(, "domain": {"size": [10, 10], "resolution": [8, 8], "orign": [0, 0]})"),
       "/domain/orign", "", "unknown field 'orign' in \"domain\" (did you mean 'origin'?)"},
      {"DomainResolutionTooSmall", with_nodes("", R"(, "domain": {"size": [10, 10], "resolution": [1, 8]})"),
       "/domain/resolution/0", "", "the resolution must be an integer from 2 to 65536, found the number 1"},
      {"DomainSizeNotPositive", with_nodes("", R"(, "domain": {"size": [10, -5], "resolution": [8, 8]})"),
       "/domain/size/1", "", "height must be greater than 0 m, found -5"},
      {"DomainMissingSize", with_nodes("", R"(, "domain": {"resolution": [8, 8]})"), "/domain/size", "",
       "missing \"size\": the world size [width, height] in metres"},
      {"NodeNotAnObject", with_nodes("\"src\""), "/nodes/0", "",
       "a node must be an object {\"id\": ..., \"type\": ...}, found the string \"src\""},
      {"MissingId", with_nodes(R"({"type": "TestSource"})"), "/nodes/0/id", "",
       "missing \"id\": every node needs a unique id"},
      {"IdNotString", with_nodes(R"({"id": 7, "type": "TestSource"})"), "/nodes/0/id", "",
       "\"id\" must be a string, found the number 7"},
      {"InvalidId", with_nodes(R"({"id": "my node", "type": "TestSource"})"), "/nodes/0/id", "my node",
       "invalid node id 'my node': use up to 128 letters, digits, '_' and '-', starting with a letter or '_'"},
      {"DuplicateId", with_nodes(kSrc + "," + kSrc), "/nodes/1/id", "src",
       "duplicate node id 'src' (already used by /nodes/0)"},
      {"MissingType", with_nodes(R"({"id": "src"})"), "/nodes/0/type", "src",
       "missing \"type\": the name of the node type"},
      {"UnknownType", with_nodes(R"({"id": "src", "type": "TestSourse", "params": {"whatever": 1}})"), "/nodes/0/type",
       "src", "unknown node type 'TestSourse' (did you mean 'TestSource'?)"},
      {"UnknownTypeLinkedBothWays",  // links to and from it are not checked, and not reported again
       with_nodes(R"({"id": "src", "type": "NoSuchThingAtAll", "inputs": {"x": "f.out"}},)" +
                  filter(R"("height": "src.height")")),
       "/nodes/0/type", "src", "unknown node type 'NoSuchThingAtAll'"},
      {"UnknownNodeField", with_nodes(R"({"id": "src", "type": "TestSource", "param": {}})"), "/nodes/0/param", "src",
       "unknown field 'param' in a node (did you mean 'params'?)"},
      {"ParamsNotObject", with_nodes(R"({"id": "src", "type": "TestSource", "params": [1]})"), "/nodes/0/params", "src",
       "\"params\" must be an object {\"name\": value, ...}, found an array of 1 element"},
      {"UnknownParam", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"octave": 3}})"),
       "/nodes/0/params/octave", "src",
       "unknown parameter 'octave' for node type TestSource (did you mean 'octaves'?)"},
      {"ParamOfTypeWithoutParams",
       with_nodes(kSrc + R"(,{"id": "p", "type": "TestPaint", "inputs": {"image": "src.color"}, "params": {"x": 1}})"),
       "/nodes/1/params/x", "p", "unknown parameter 'x' for node type TestPaint (it has no parameters)"},
      {"WrongValueType", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"octaves": "six"}})"),
       "/nodes/0/params/octaves", "src", "parameter 'octaves' (int): expected an integer, found the string \"six\""},
      {"ValueOutOfRange", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"octaves": 40}})"),
       "/nodes/0/params/octaves", "src", "parameter 'octaves' (int): value 40 is above the maximum 16"},
      {"BadEnumChoice", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"basis": "perlinn"}})"),
       "/nodes/0/params/basis", "src",
       "parameter 'basis' (enum): 'perlinn' is not one of: perlin, value, simplex (did you mean 'perlin'?)"},
      {"NegativeSeed", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"seed": -1}})"),
       "/nodes/0/params/seed", "src", "parameter 'seed' (seed): a seed must not be negative, found -1"},
      {"BoolAsNumber", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"enabled": 1}})"),
       "/nodes/0/params/enabled", "src", "parameter 'enabled' (bool): expected true or false, found the number 1"},
      {"ShortColour", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"tint": [1, 0]}})"),
       "/nodes/0/params/tint", "src",
       "parameter 'tint' (color): expected a color [r, g, b] or [r, g, b, a], found an array of 2 elements"},
      {"Vec3ComponentNotNumber",
       with_nodes(R"({"id": "src", "type": "TestSource", "params": {"direction": [0, "up", 1]}})"),
       "/nodes/0/params/direction", "src",
       "parameter 'direction' (vec3): component 1: expected a number, found the string \"up\""},
      {"CurveNotIncreasing",
       with_nodes(R"({"id": "src", "type": "TestSource", "params": {"remap": [[0, 0], [0.5, 1], [0.5, 0.2]]}})"),
       "/nodes/0/params/remap", "src", "parameter 'remap' (curve): curve points must have strictly increasing x"},
      {"GradientStopMalformed",
       with_nodes(R"({"id": "src", "type": "TestSource", "params": {"palette": [[0, [0, 0, 0]], [1, "white"]]}})"),
       "/nodes/0/params/palette", "src",
       "parameter 'palette' (gradient): stop 1: color: expected a color [r, g, b] or [r, g, b, a], found the "
       "string \"white\""},
      {"WrongFileExtension", with_nodes(R"({"id": "src", "type": "TestSource", "params": {"file": "h.jpg"}})"),
       "/nodes/0/params/file", "src", "parameter 'file' (path): file extension must be one of: .exr, .png"},
      {"LinkSyntax", with_nodes(kSrc + "," + filter(R"("height": "src")")), "/nodes/1/inputs/height", "f",
       "malformed link \"src\": expected \"node.port\", the id of a node and one of its outputs"},
      {"LinkNotString", with_nodes(kSrc + "," + filter(R"("height": ["src", "height"])")), "/nodes/1/inputs/height",
       "f", "a link must be a string \"node.port\", found an array of 2 elements"},
      {"LinkToMissingNode", with_nodes(kSrc + "," + filter(R"("height": "srx.height")")), "/nodes/1/inputs/height", "f",
       "link to missing node 'srx' (did you mean 'src'?)"},
      {"LinkToMissingOutput", with_nodes(kSrc + "," + filter(R"("height": "src.heigth")")), "/nodes/1/inputs/height",
       "f", "link to missing output 'heigth' of node 'src' (TestSource) (did you mean 'height'?)"},
      {"UnknownInputPort", with_nodes(kSrc + "," + filter(R"("height": "src.height", "masks": "src.height")")),
       "/nodes/1/inputs/masks", "f", "unknown input 'masks' for node type TestFilter (did you mean 'mask'?)"},
      {"TypeMismatch", with_nodes(kSrc + "," + filter(R"("height": "src.color")")), "/nodes/1/inputs/height", "f",
       "type mismatch: src.color is Image but input 'height' of TestFilter takes Heightfield"},
      {"MissingRequiredInput", with_nodes(kSrc + "," + filter(R"("mask": "src.height")")), "/nodes/1/inputs/height",
       "f", "missing required input 'height' (Heightfield) of node type TestFilter"},
      {"Cycle", with_nodes(R"({"id": "a", "type": "TestFilter", "inputs": {"height": "b.out"}},
                     {"id": "b", "type": "TestFilter", "inputs": {"height": "a.out"}})"),
       "/nodes/1/inputs/height", "b", "the links form a cycle: a -> b -> a"},
      {"SelfLink", with_nodes(R"({"id": "a", "type": "TestFilter", "inputs": {"height": "a.out"}})"),
       "/nodes/0/inputs/height", "a", "the links form a cycle: a -> a"},
      {"EditorPositionForUnknownNode", with_nodes(kSrc, R"(, "editor": {"positions": {"ghost": [0, 0]}})"),
       "/editor/positions/ghost", "ghost", "editor position for unknown node 'ghost'"},
      {"EditorPositionNotNumbers", with_nodes(kSrc, R"(, "editor": {"positions": {"src": [0, "left"]}})"),
       "/editor/positions/src/1", "src", "expected a number, found the string \"left\""},
      {"UnknownEditorField", with_nodes(kSrc, R"(, "editor": {"zoom": 2})"), "/editor/zoom", "",
       "unknown field 'zoom' in \"editor\" (expected one of: positions)"},
  };
}

class MalformedFile : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedFile, GivesItsOwnDiagnostic) {
  const Malformed& c = GetParam();
  const auto r = parse_graph(c.text);
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u) << r.error_text();
  const auto& d = r.diagnostics[0];
  EXPECT_EQ(d.path, c.path);
  EXPECT_EQ(d.node, c.node);
  if (c.prefix_only)
    EXPECT_THAT(d.message, StartsWith(c.message));
  else
    EXPECT_EQ(d.message, c.message);
}

INSTANTIATE_TEST_SUITE_P(GraphFile, MalformedFile, ::testing::ValuesIn(malformed_cases()),
                         [](const ::testing::TestParamInfo<Malformed>& info) { return info.param.name; });

TEST(GraphFile, EveryExampleGraphRoundTrips) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "graphs")) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const auto loaded = load_graph_file(entry.path());
    ASSERT_TRUE(loaded.ok()) << entry.path() << "\n" << loaded.error_text();
    const std::string text = serialize_graph(*loaded.graph);
    const auto again = parse_graph(text);
    ASSERT_TRUE(again.ok()) << again.error_text();
    EXPECT_TRUE(*again.graph == *loaded.graph) << entry.path();
    EXPECT_EQ(serialize_graph(*again.graph), text) << entry.path();
  }
  EXPECT_GT(count, 0);
}

TEST(GraphFile, EveryProblemInAFileIsReported) {
  const std::string text = R"({
  "format": "orogen-graph",
  "version": 1,
  "domain": {"size": [100, 100], "resolution": [70000, 64]},
  "nodes": [
    {"id": "src", "type": "TestSource", "params": {"octaves": 0, "tnit": [1, 1, 1]}},
    {"id": "noise", "type": "FMB"},
    {"id": "f", "type": "TestFilter", "inputs": {"height": "src.color", "mask": "nowhere.out"}},
    {"id": "a", "type": "TestFilter", "inputs": {"height": "b.out"}},
    {"id": "b", "type": "TestFilter", "inputs": {"height": "a.out"}},
    {"id": "lonely", "type": "TestFilter"},
    {"id": "src", "type": "TestPaint", "inputs": {"image": "src.color"}}
  ],
  "editor": {"positions": {"ghost": [1, 2]}},
  "comment": "not allowed"
})";
  const auto r = parse_graph(text);
  ASSERT_FALSE(r.ok());
  std::vector<std::pair<std::string, std::string>> where;
  for (const auto& d : r.diagnostics) where.emplace_back(d.path, d.node);
  const std::vector<std::pair<std::string, std::string>> expected{
      {"/comment", ""},
      {"/domain/resolution/0", ""},
      {"/nodes/0/params/octaves", "src"},
      {"/nodes/0/params/tnit", "src"},
      {"/nodes/1/type", "noise"},
      {"/nodes/2/inputs/height", "f"},
      {"/nodes/2/inputs/mask", "f"},
      {"/nodes/4/inputs/height", "b"},
      {"/nodes/5/inputs/height", "lonely"},
      {"/nodes/6/id", "src"},
      {"/editor/positions/ghost", "ghost"},
  };
  EXPECT_EQ(where, expected) << r.error_text();
  // The unknown parameter comes with a suggestion.
  EXPECT_THAT(r.error_text(), HasSubstr("did you mean 'tint'?"));
}

}  // namespace
TEST(GraphFilePartial, KeepsWhatCanBeReadWithEveryProblemListed) {
  const std::string text = R"({"format": "orogen-graph", "version": 1,
    "nodes": [
      {"id": "src", "type": "TestSource", "params": {"scale": 500, "octaves": 3}},
      {"id": "f", "type": "TestFilter", "inputs": {"height": "src.color"}},
      {"id": "ghost", "type": "Erode", "params": {"iterations": 10}, "inputs": {"height": "src.height"}},
      {"id": "g", "type": "TestFilter", "inputs": {"height": "ghost.out", "mask": "nowhere.out"}},
      {"id": "c1", "type": "TestFilter", "inputs": {"height": "c2.out"}},
      {"id": "c2", "type": "TestFilter", "inputs": {"height": "c1.out"}}
    ],
    "editor": {"positions": {"ghost": [10, 20]}}})";
  // Without the option: no graph, as before.
  EXPECT_FALSE(parse_graph(text).graph.has_value());
  LoadOptions options;
  options.keep_partial = true;
  options.allow_unconnected_inputs = true;
  const LoadResult r = parse_graph(text, options);
  ASSERT_TRUE(r.graph.has_value());
  EXPECT_FALSE(r.ok()) << "a partial graph is not ok";
  const Graph& g = *r.graph;
  EXPECT_EQ(g.nodes().size(), 6u);
  // The invalid value keeps its default; the valid one is read.
  EXPECT_EQ(std::get<double>(g.param("src", "scale")), 1.0);
  EXPECT_EQ(std::get<std::int64_t>(g.param("src", "octaves")), 3);
  // The unknown type is a placeholder with the ports its links use, connected, at its position.
  const Node& ghost = g.at("ghost");
  EXPECT_EQ(ghost.type->name, "Erode");
  ASSERT_NE(ghost.type->find_input("height"), nullptr);
  EXPECT_EQ(ghost.type->find_input("height")->type, PortType::Heightfield);
  ASSERT_NE(ghost.type->find_output("out"), nullptr);
  EXPECT_EQ(ghost.inputs.at("height"), (PortRef{"src", "height"}));
  EXPECT_EQ(g.at("g").inputs.at("height"), (PortRef{"ghost", "out"}));
  EXPECT_EQ(g.editor.positions.at("ghost"), glm::dvec2(10, 20));
  // Broken links are left out and listed with their reason; one link of the cycle is cut.
  EXPECT_FALSE(g.at("f").inputs.count("height"));
  EXPECT_FALSE(g.at("g").inputs.count("mask"));
  EXPECT_NO_THROW(g.topological_order());
  auto dropped = [&](const std::string& node, const std::string& port) {
    return std::any_of(r.dropped_links.begin(), r.dropped_links.end(), [&](const DroppedLink& d) {
      return d.to_node == node && d.to_port == port && !d.reason.empty();
    });
  };
  EXPECT_TRUE(dropped("f", "height"));
  EXPECT_TRUE(dropped("g", "mask"));
  EXPECT_TRUE(dropped("c1", "height") || dropped("c2", "height"));
  EXPECT_EQ(r.dropped_links.size(), 3u);
  // Every problem is a diagnostic naming its node.
  std::set<std::string> flagged;
  for (const auto& d : r.diagnostics) flagged.insert(d.node);
  for (const char* id : {"src", "f", "ghost", "g"}) EXPECT_TRUE(flagged.count(id)) << id;
  // The placeholder fails with the reason when evaluated; saving keeps its type name.
  EXPECT_NE(serialize_graph(g).find("\"Erode\""), std::string::npos);
}

}  // namespace orogen
