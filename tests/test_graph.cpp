// The Graph API: nodes and ids, type-checked links, cycle rejection, parameters, and graph traversal.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "graph/exec_context.h"
#include "graph/graph.h"
#include "graph/registry.h"

namespace orogen {

// Test node types of this file.
OROGEN_NODE(TestGen) {
  b.category("test").description("A generator with a field and an image output.");
  b.output("out", PortType::Heightfield).description("Field");
  b.output("img", PortType::Image).description("Image");
  b.param_float("height", 2.0).range(0.0, 10.0).unit(Unit::Metre).description("Height");
  b.param_int("count", 3).unit(Unit::Count).range(1, 5).description("Count");
  b.param_enum("mode", {"add", "max"}, "add").description("Mode");
  b.param_vec2("offset", {0.0, 0.0}).range(-1.0, 1.0).unit(Unit::Metre).description("Offset");
  b.param_seed("seed", 1).description("Seed");
  b.execute([](ExecContext&) {});
}

OROGEN_NODE(TestOp) {
  b.category("test").description("Combines a required and an optional field.");
  b.input("a", PortType::Heightfield).description("First");
  b.input("b", PortType::Heightfield).optional().description("Second");
  b.output("out", PortType::Heightfield).description("Result");
  b.execute([](ExecContext&) {});
}

OROGEN_NODE(TestImageOp) {
  b.category("test").description("Takes an image and points.");
  b.input("img", PortType::Image).description("Image");
  b.input("pts", PortType::Points).optional().description("Points");
  b.output("out", PortType::Image).description("Image");
  b.execute([](ExecContext&) {});
}

namespace {

using ::testing::HasSubstr;

// gmock's container matchers need the gmock library, which the tests do not link: compare sorted copies.
std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}
using Ids = std::vector<std::string>;

template <class F>
std::string graph_error(F&& f) {
  try {
    f();
  } catch (const GraphError& e) {
    return e.what();
  }
  return "(no error)";
}

// gen -> x, gen -> y, (x, y) -> z: a diamond.
Graph diamond() {
  Graph g;
  g.add_node("TestGen", "gen");
  g.add_node("TestOp", "x");
  g.add_node("TestOp", "y");
  g.add_node("TestOp", "z");
  g.connect({"gen", "out"}, "x", "a");
  g.connect({"gen", "out"}, "y", "a");
  g.connect({"x", "out"}, "z", "a");
  g.connect({"y", "out"}, "z", "b");
  return g;
}

TEST(Graph, AddNodeMakesUniqueIdsFromTheTypeName) {
  Graph g;
  EXPECT_EQ(g.add_node("TestGen").id, "testgen");
  EXPECT_EQ(g.add_node("TestGen").id, "testgen2");
  EXPECT_EQ(g.add_node("TestGen").id, "testgen3");
  EXPECT_EQ(g.add_node("TestOp", "my_op-1").id, "my_op-1");
  ASSERT_EQ(g.nodes().size(), 4u);
  EXPECT_EQ(g.at("testgen2").type, NodeRegistry::instance().find("TestGen"));
  EXPECT_EQ(g.unique_id("testgen"), "testgen4");
  EXPECT_EQ(g.unique_id("Fresh"), "fresh");
  EXPECT_EQ(g.unique_id("9 bad"), "node");
}

TEST(Graph, AddNodeRejectsBadIdsAndUnknownTypes) {
  Graph g;
  g.add_node("TestGen", "a");
  EXPECT_EQ(graph_error([&] { g.add_node("TestGen", "a"); }), "duplicate node id 'a'");
  for (const std::string& bad : std::vector<std::string>{"1a", "a.b", "a b", "-a", std::string(129, 'a')})
    EXPECT_THAT(graph_error([&] { g.add_node("TestGen", bad); }), HasSubstr("invalid node id")) << bad;
  EXPECT_EQ(graph_error([&] { g.add_node("TestGenn"); }), "unknown node type 'TestGenn' (did you mean 'TestGen'?)");
  EXPECT_EQ(g.nodes().size(), 1u);
  EXPECT_TRUE(Graph::valid_id("_x9-y"));
  EXPECT_TRUE(Graph::valid_id(std::string(128, 'a')));
  EXPECT_FALSE(Graph::valid_id(""));
  EXPECT_EQ(graph_error([&] { (void)g.at("nope"); }), "no node 'nope'");
  EXPECT_EQ(g.find("nope"), nullptr);
}

TEST(Graph, LinksAreTypeChecked) {
  Graph g;
  g.add_node("TestGen", "gen");
  g.add_node("TestOp", "op");
  g.add_node("TestImageOp", "paint");
  EXPECT_EQ(g.check_link({"gen", "out"}, "op", "a"), "");
  EXPECT_EQ(g.check_link({"gen", "img"}, "op", "a"), "type mismatch: gen.img is Image but op.a takes Heightfield");
  EXPECT_EQ(g.check_link({"gen", "out"}, "paint", "img"),
            "type mismatch: gen.out is Heightfield but paint.img takes Image");
  EXPECT_EQ(g.check_link({"gen", "nope"}, "op", "a"), "node 'gen' (TestGen) has no output 'nope'");
  EXPECT_EQ(g.check_link({"gen", "out"}, "op", "c"), "node 'op' (TestOp) has no input 'c'");
  EXPECT_EQ(g.check_link({"ghost", "out"}, "op", "a"), "no node 'ghost'");
  EXPECT_EQ(g.check_link({"gen", "out"}, "ghost", "a"), "no node 'ghost'");
  EXPECT_EQ(graph_error([&] {
              g.connect({"gen", "img"}, "op", "a");
            }),
            "type mismatch: gen.img is Image but op.a takes Heightfield");
  EXPECT_TRUE(g.at("op").inputs.empty());  // a refused link changes nothing

  g.connect({"gen", "out"}, "op", "a");
  g.connect({"gen", "img"}, "paint", "img");
  EXPECT_EQ(g.at("op").inputs.at("a"), (PortRef{"gen", "out"}));
  EXPECT_EQ(g.at("paint").inputs.at("img"), (PortRef{"gen", "img"}));
  EXPECT_EQ(PortRef({"gen", "out"}).str(), "gen.out");
}

TEST(Graph, ConnectReplacesTheLinkOnAnInputAndDisconnectRemovesIt) {
  Graph g;
  g.add_node("TestGen", "g1");
  g.add_node("TestGen", "g2");
  g.add_node("TestOp", "op");
  g.connect({"g1", "out"}, "op", "a");
  g.connect({"g2", "out"}, "op", "a");
  ASSERT_EQ(g.at("op").inputs.size(), 1u);
  EXPECT_EQ(g.at("op").inputs.at("a").node, "g2");
  g.connect({"g1", "out"}, "op", "b");
  g.disconnect("op", "a");
  EXPECT_EQ(g.at("op").inputs.count("a"), 0u);
  EXPECT_EQ(g.at("op").inputs.count("b"), 1u);
  g.disconnect("op", "a");  // disconnecting a free input is harmless
  EXPECT_EQ(graph_error([&] { g.disconnect("ghost", "a"); }), "no node 'ghost'");
}

TEST(Graph, CyclesAreRefused) {
  Graph g = diamond();
  const Graph before = g;
  EXPECT_EQ(g.check_link({"z", "out"}, "x", "b"), "linking z.out to x.b would make a cycle");
  EXPECT_EQ(graph_error([&] { g.connect({"z", "out"}, "x", "b"); }), "linking z.out to x.b would make a cycle");
  EXPECT_EQ(graph_error([&] { g.connect({"x", "out"}, "x", "b"); }), "a node cannot feed itself (x)");
  EXPECT_TRUE(g == before);
  // The same link between unrelated branches is fine.
  EXPECT_EQ(g.check_link({"x", "out"}, "y", "b"), "");
}

// Random edits: connect succeeds exactly when the link is well typed and the target does not already feed
// the source, checked against a brute-force reachability search; the graph always stays acyclic.
TEST(Graph, RandomEditsAgreeWithBruteForceReachability) {
  Graph g;
  for (int i = 0; i < 20; ++i) {
    std::string id = i < 4 ? "g" : "o";
    id += std::to_string(i);  // (not "g" + to_string(i): GCC 12 gives a false -Wrestrict warning)
    g.add_node(i < 4 ? "TestGen" : "TestOp", id);
  }
  auto feeds = [&](const std::string& from, const std::string& to) {  // does `from` reach `to` along links?
    std::set<std::string> seen{from};
    std::vector<std::string> todo{from};
    while (!todo.empty()) {
      const auto cur = todo.back();
      todo.pop_back();
      if (cur == to) return true;
      for (const auto& n : g.nodes())
        for (const auto& [port, src] : n.inputs)
          if (src.node == cur && seen.insert(n.id).second) todo.push_back(n.id);
    }
    return false;
  };
  std::uint64_t state = 12345;
  auto rnd = [&](std::size_t n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::size_t>((state >> 33) % n);
  };
  int accepted = 0, refused_cycles = 0;
  for (int step = 0; step < 400; ++step) {
    const auto& src = g.nodes()[rnd(g.nodes().size())];
    const auto& dst = g.nodes()[4 + rnd(16)];
    const std::string from = src.id, to = dst.id, port = rnd(2) ? "a" : "b";
    const bool would_cycle = from == to || feeds(to, from);
    const std::string why = g.check_link({from, "out"}, to, port);
    EXPECT_EQ(why.empty(), !would_cycle) << from << " -> " << to << ": " << why;
    if (why.empty()) {
      g.connect({from, "out"}, to, port);
      ++accepted;
    } else {
      ++refused_cycles;
    }
    if (rnd(5) == 0) g.disconnect(to, port);
    ASSERT_NO_THROW(g.topological_order());
  }
  EXPECT_GT(accepted, 50);
  EXPECT_GT(refused_cycles, 10);
}

TEST(Graph, RemoveNodeDropsItsLinksAndPosition) {
  Graph g = diamond();
  g.editor.positions["x"] = {1, 2};
  g.editor.positions["y"] = {3, 4};
  g.remove_node("x");
  EXPECT_EQ(g.find("x"), nullptr);
  EXPECT_EQ(g.nodes().size(), 3u);
  EXPECT_EQ(g.at("z").inputs.count("a"), 0u);
  EXPECT_EQ(g.at("z").inputs.at("b").node, "y");
  EXPECT_EQ(g.editor.positions.count("x"), 0u);
  EXPECT_EQ(g.editor.positions.count("y"), 1u);
  // The index is rebuilt: lookups after removal find the right nodes.
  EXPECT_EQ(g.at("z").id, "z");
  EXPECT_EQ(g.at("y").type->name, "TestOp");
  EXPECT_EQ(graph_error([&] { g.remove_node("x"); }), "no node 'x'");
}

TEST(Graph, RenameNodeUpdatesLinksAndPosition) {
  Graph g = diamond();
  g.editor.positions["gen"] = {5, 6};
  g.rename_node("gen", "base");
  EXPECT_EQ(g.find("gen"), nullptr);
  EXPECT_EQ(g.at("base").type->name, "TestGen");
  EXPECT_EQ(g.at("x").inputs.at("a"), (PortRef{"base", "out"}));
  EXPECT_EQ(g.at("y").inputs.at("a"), (PortRef{"base", "out"}));
  EXPECT_EQ(g.editor.positions.at("base"), glm::dvec2(5, 6));
  EXPECT_EQ(g.editor.positions.count("gen"), 0u);
  EXPECT_EQ(graph_error([&] { g.rename_node("base", "x"); }), "duplicate node id 'x'");
  EXPECT_EQ(graph_error([&] { g.rename_node("base", "a.b"); }), "invalid node id 'a.b'");
  EXPECT_EQ(graph_error([&] { g.rename_node("ghost", "g2"); }), "no node 'ghost'");
  g.rename_node("base", "base");  // no-op
  EXPECT_EQ(g.upstream("z").size(), 3u);
}

TEST(Graph, SetParamChecksTypeAndRange) {
  Graph g;
  g.add_node("TestGen", "gen");
  g.set_param("gen", "height", 7.5);
  EXPECT_EQ(std::get<double>(g.param("gen", "height")), 7.5);
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "height", 10.5); }), "gen.height: value 10.5 is above the maximum 10");
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "height", -1.0); }), "gen.height: value -1 is below the minimum 0");
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "height", std::int64_t{3}); }),
            "gen.height: expected a value of type float");
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "height", std::nan("")); }),
            "gen.height: value must be a finite number");
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "count", std::int64_t{6}); }),
            "gen.count: value 6 is above the maximum 5");
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "mode", std::string("min")); }),
            "gen.mode: 'min' is not one of: add, max");
  EXPECT_THAT(graph_error([&] { g.set_param("gen", "offset", glm::dvec2(0.5, 2.0)); }), HasSubstr("maximum 1"));
  EXPECT_EQ(graph_error([&] { g.set_param("gen", "heigth", 1.0); }), "node 'gen' (TestGen) has no parameter 'heigth'");
  EXPECT_EQ(graph_error([&] { g.set_param("ghost", "height", 1.0); }), "no node 'ghost'");
  // Refused values leave the last good one.
  EXPECT_EQ(std::get<double>(g.param("gen", "height")), 7.5);
  EXPECT_EQ(g.at("gen").params.size(), 1u);
}

TEST(Graph, EffectiveParamsAreExplicitValuesOrDefaultsInDeclarationOrder) {
  Graph g;
  g.add_node("TestGen", "gen");
  g.set_param("gen", "mode", std::string("max"));
  g.set_param("gen", "seed", std::uint64_t{99});
  const auto values = g.effective_params(g.at("gen"));
  ASSERT_EQ(values.size(), 5u);
  EXPECT_EQ(std::get<double>(values[0]), 2.0);
  EXPECT_EQ(std::get<std::int64_t>(values[1]), 3);
  EXPECT_EQ(std::get<std::string>(values[2]), "max");
  EXPECT_EQ(std::get<glm::dvec2>(values[3]), glm::dvec2(0.0));
  EXPECT_EQ(std::get<std::uint64_t>(values[4]), 99u);
  EXPECT_EQ(std::get<std::int64_t>(g.param("gen", "count")), 3);
  g.reset_param("gen", "mode");
  EXPECT_EQ(std::get<std::string>(g.param("gen", "mode")), "add");
  EXPECT_EQ(g.at("gen").params.count("mode"), 0u);
  EXPECT_EQ(graph_error([&] { (void)g.param("gen", "nope"); }), "node 'gen' (TestGen) has no parameter 'nope'");
}

TEST(Graph, TopologicalOrderPutsEveryNodeAfterItsInputs) {
  Graph g;
  // Added in reverse dependency order so that file order alone would be wrong.
  g.add_node("TestOp", "z");
  g.add_node("TestOp", "y");
  g.add_node("TestOp", "x");
  g.add_node("TestGen", "gen");
  g.add_node("TestGen", "alone");
  g.connect({"gen", "out"}, "x", "a");
  g.connect({"x", "out"}, "y", "a");
  g.connect({"gen", "out"}, "y", "b");
  g.connect({"y", "out"}, "z", "a");
  const auto order = g.topological_order();
  ASSERT_EQ(order.size(), 5u);
  auto pos = [&](const std::string& id) { return std::find(order.begin(), order.end(), id) - order.begin(); };
  for (const auto& n : g.nodes())
    for (const auto& [port, src] : n.inputs) EXPECT_LT(pos(src.node), pos(n.id)) << src.node << " -> " << n.id;
  EXPECT_EQ(order, g.topological_order());  // stable
  EXPECT_EQ(order, (std::vector<std::string>{"gen", "x", "y", "z", "alone"}));
}

TEST(Graph, TopologicalOrderDetectsACycleMadeBehindTheApisBack) {
  Graph g = diamond();
  g.find("x")->inputs["b"] = PortRef{"z", "out"};  // bypasses connect()'s check
  EXPECT_THAT(graph_error([&] { (void)g.topological_order(); }), HasSubstr("cycle"));
}

TEST(Graph, UpstreamAndDownstreamAreTransitive) {
  Graph g = diamond();
  g.add_node("TestGen", "other");
  EXPECT_EQ(sorted(g.upstream("z")), (Ids{"gen", "x", "y"}));
  EXPECT_EQ(sorted(g.upstream("x")), (Ids{"gen"}));
  EXPECT_TRUE(g.upstream("gen").empty());
  EXPECT_EQ(sorted(g.downstream("gen")), (Ids{"x", "y", "z"}));
  EXPECT_EQ(sorted(g.downstream("y")), (Ids{"z"}));
  EXPECT_TRUE(g.downstream("z").empty());
  EXPECT_TRUE(g.downstream("other").empty());
  EXPECT_TRUE(g.upstream("other").empty());
}

TEST(Graph, UpstreamStopsAtTheNodesItIsToldTo) {
  const Graph g = diamond();  // gen feeds x and y, which feed z
  const auto at = [](std::set<std::string> ids) { return [ids](const std::string& id) { return ids.count(id) > 0; }; };
  EXPECT_EQ(sorted(g.upstream("z", at({"x"}))), (Ids{"gen", "x", "y"}));  // gen still reaches z through y
  EXPECT_EQ(sorted(g.upstream("z", at({"x", "y"}))), (Ids{"x", "y"}));
  EXPECT_EQ(sorted(g.upstream("z", at({"gen"}))), (Ids{"gen", "x", "y"}));
  EXPECT_EQ(sorted(g.upstream("x", at({"gen"}))), (Ids{"gen"}));
}

TEST(Graph, EqualityComparesEverythingThatIsSaved) {
  const Graph a = diamond();
  Graph b = diamond();
  EXPECT_TRUE(a == b);
  b.set_param("gen", "height", 1.0);
  EXPECT_FALSE(a == b);
  b = diamond();
  b.editor.positions["x"] = {0, 0};
  EXPECT_FALSE(a == b);
  b = diamond();
  b.domain.resolution = {512, 512};
  EXPECT_FALSE(a == b);
  b = diamond();
  b.disconnect("z", "b");
  EXPECT_FALSE(a == b);
  b = diamond();
  b.rename_node("x", "x2");
  EXPECT_FALSE(a == b);
}

TEST(Graph, DomainCoversTheWorldRectangleWithSharedBorders) {
  GraphDomain d;
  d.origin = {100.0, -50.0};
  d.size = {1000.0, 500.0};
  d.resolution = {11, 6};
  const Domain dom = d.to_domain();
  EXPECT_EQ(dom.min_corner(), glm::dvec2(100.0, -50.0));
  EXPECT_EQ(dom.max_corner(), glm::dvec2(1100.0, 450.0));
  EXPECT_EQ(dom.spacing, glm::dvec2(100.0, 100.0));
  EXPECT_EQ(dom.width(), 11);
  EXPECT_EQ(dom.height(), 6);
}

}  // namespace
}  // namespace orogen
