// Every node type says how it runs across ranks in a distributed build (graph/distribution.h): derived from its
// reach when that is point-wise or local, declared when it can be global, checked at registration.
#include <gtest/gtest.h>

#include "graph/registry.h"
#include "support/registered_types.h"

namespace orogen::test {
namespace {

std::vector<ParamValue> defaults(const NodeType& t) {
  std::vector<ParamValue> v;
  for (const auto& p : t.params) v.push_back(p.default_value);
  return v;
}

class DistributionContract : public testing::TestWithParam<std::string> {};

TEST_P(DistributionContract, DeclaredOrDerivedFromTheReach) {
  const NodeType& t = *NodeRegistry::instance().find(GetParam());
  const Distribution d = t.distribution_for(defaults(t));
  EXPECT_NE(d, Distribution::Undeclared) << t.name << " cannot run distributed";
  if (!t.reach_for(defaults(t)).is_global()) {
    EXPECT_EQ(d, Distribution::PerTile) << t.name;
  }
  if (t.can_be_global() && !t.writes_files && !t.domain_independent) {
    EXPECT_TRUE(t.distribution != Distribution::Undeclared || t.distribution_fn)
        << t.name << ": a global reach needs a declared kind";
  }
  EXPECT_STRNE(describe(d), describe(Distribution::Undeclared));
}

INSTANTIATE_TEST_SUITE_P(Registry, DistributionContract, testing::ValuesIn(registered_type_names()), type_test_name);

Distribution kind_of(const char* name, std::vector<std::pair<std::string, ParamValue>> edits = {}) {
  const NodeType* t = NodeRegistry::instance().find(name);
  EXPECT_NE(t, nullptr) << name;
  if (!t) return Distribution::Undeclared;
  auto params = defaults(*t);
  for (auto& [param, value] : edits) params[static_cast<std::size_t>(t->param_index(param))] = value;
  return t->distribution_for(params);
}

TEST(NodeDistribution, KindsOfTheHydrologyCoreReductionsWritersAndGenerators) {
  for (const char* n : {"FillDepressions", "FlowDirection", "FlowAccumulation", "Watersheds", "Lakes", "FloodFill",
                        "RiverExtract", "DrainageMetrics"})
    EXPECT_EQ(kind_of(n), Distribution::TileGraph) << n;
  EXPECT_EQ(kind_of("Normalize"), Distribution::Reduction);
  EXPECT_EQ(kind_of("Curve"), Distribution::PerTile);  // a fixed range: point-wise
  EXPECT_EQ(kind_of("Curve", {{"range", std::string("field")}}), Distribution::Reduction);
  EXPECT_EQ(kind_of("Blur"), Distribution::PerTile);
  EXPECT_EQ(kind_of("WriteHeightfield"), Distribution::PerTile);
  EXPECT_EQ(kind_of("LSystem"), Distribution::Replicated);
  EXPECT_EQ(kind_of("ThermalErosion"), Distribution::HaloExchange);
  EXPECT_EQ(kind_of("HydraulicErosion"), Distribution::HaloExchange);
  EXPECT_EQ(kind_of("WaterFlow"), Distribution::HaloExchange);
  // PoissonDisk fills up to the edges of the domain it is asked for only with fill_border.
  EXPECT_EQ(kind_of("PoissonDisk"), Distribution::Gathered);
  EXPECT_EQ(kind_of("PoissonDisk", {{"fill_border", false}}), Distribution::PerTile);
  EXPECT_TRUE(runs_across_ranks(Distribution::PerTile));
  EXPECT_FALSE(runs_across_ranks(Distribution::TileGraph));
}

TEST(NodeDistribution, AGlobalNodeWithoutAKindIsRefusedAtRegistration) {
  NodeType t;
  t.name = "GlobalWithoutKind";
  NodeBuilder b(t);
  b.category("test").description("test");
  b.reach_global();
  b.output("out", PortType::Heightfield).description("out");
  b.execute([](ExecContext&) {});
  try {
    check_declaration(t);
    ADD_FAILURE() << "accepted";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("must declare how it runs across ranks"), std::string::npos) << e.what();
  }
  b.distribution(Distribution::Gathered);
  EXPECT_NO_THROW(check_declaration(t));
  // A distribution function is a declaration too, with a summary for the node reference.
  t.distribution = Distribution::Undeclared;
  b.distribution([](const ParamView&) { return Distribution::Gathered; }, "");
  EXPECT_THROW(check_declaration(t), std::logic_error);
  b.distribution([](const ParamView&) { return Distribution::Gathered; }, "always gathered");
  EXPECT_NO_THROW(check_declaration(t));
  // A reach function may make the reach global: it needs a kind too.
  NodeType f;
  f.name = "ReachFunction";
  NodeBuilder fb(f);
  fb.category("test").description("test");
  fb.reach([](const ParamView&) { return Reach::pointwise(); }, "point-wise");
  fb.execute([](ExecContext&) {});
  EXPECT_THROW(check_declaration(f), std::logic_error);
}

}  // namespace
}  // namespace orogen::test
