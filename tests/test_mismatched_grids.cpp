// The one rule for rasters on different grids (nodes/common/match_domain.h), checked over the whole registry:
// every node type with two or more Heightfield/Image inputs is fed, one secondary port at a time, a raster
// on another grid (offset, coarser spacing, covering only part of the primary's rectangle). It must run and
// give exactly what it gives when that input is first resampled onto the primary's domain explicitly; a
// raster that does not overlap the primary at all must fail with the one message, naming node and port.
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "evaluator/value_serialization.h"
#include "field_ops_fixtures.h"
#include "graph/exec_context.h"
#include "graph/image.h"
#include "graph/points.h"
#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/resample.h"

namespace orogen {
namespace {

bool is_raster(PortType t) { return t == PortType::Heightfield || t == PortType::Image; }

// The primary raster port: `in`, or `a` for binary operators; null when the node has neither as a raster
// (generators work on their requested domain, placement nodes on points).
const PortDecl* primary_port(const NodeType& t) {
  for (const char* name : {"in", "a"})
    for (const auto& p : t.inputs)
      if (p.name == name && is_raster(p.type)) return &p;
  return nullptr;
}

// Placement nodes sample their fields at each point's world position instead of resampling them: no raster
// primary, and points out.
bool samples_in_world_space(const NodeType& t) {
  if (primary_port(t)) return false;
  for (const auto& o : t.outputs)
    if (o.type == PortType::Points) return true;
  return false;
}

// Smooth values of the kind each port expects, from world positions (so any grid samples the same surface).
double value_at(const std::string& port, double x, double y) {
  if (port == "dx" || port == "dy" || port.rfind("warp_", 0) == 0 || port == "distance_offset")
    return 30.0 * std::sin((port.back() == 'y' ? x : y) / 140.0);  // metres of displacement
  if (port == "in" || port == "a" || port == "b" || port == "height") return test::rolling_hills(x, y);  // metres
  return 0.5 + 0.4 * std::sin(x / 170.0 + y / 230.0);  // masks, weights, rates in 0..1
}

PortValue raster_on(const PortDecl& port, const Domain& d) {
  if (port.type == PortType::Image) {  // 12 channels: monthly climate images, layer weights, colors
    auto img = std::make_shared<Image>(d, 12);
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i)
        for (int c = 0; c < 12; ++c)
          img->pixel(i, j)[c] = static_cast<float>(0.5 + 0.3 * std::sin(d.x(i) / (150.0 + 10 * c) + d.y(j) / 210.0));
    return PortValue(ImagePtr(img));
  }
  return PortValue(test::field_from(d, [&](double x, double y) { return value_at(port.name, x, y); }));
}

PortValue resampled_onto(const PortValue& v, const Domain& d) {
  if (const auto* f = std::get_if<HeightfieldPtr>(&v))
    return PortValue(HeightfieldPtr(std::make_shared<Heightfield>(resample_bilinear(**f, d))));
  return PortValue(ImagePtr(std::make_shared<Image>(resample_bilinear(*std::get<ImagePtr>(v), d))));
}

// A few points over the primary domain, for placement nodes that take points.
PortValue some_points() {
  auto p = std::make_shared<Points>();
  for (int k = 0; k < 12; ++k) p->add({static_cast<float>(-150 + 47 * k), static_cast<float>(130 + 31 * k), 0.0f});
  return PortValue(PointsPtr(p));
}

// Every input of `t` on `primary`; ports of other types get a fixture when the node needs them.
std::map<std::string, PortValue> inputs_on(const NodeType& t, const Domain& primary) {
  std::map<std::string, PortValue> in;
  for (const auto& p : t.inputs) {
    if (is_raster(p.type))
      in[p.name] = raster_on(p, primary);
    else if (p.type == PortType::Points)
      in[p.name] = some_points();
    else if (!p.optional)
      ADD_FAILURE() << t.name << ": no fixture for required input '" << p.name << "'";
  }
  return in;
}

// The node's domain (20 m spacing), a secondary grid that overlaps part of it with 28 m spacing and an offset
// that puts no sample on the primary's lattice, and a grid far away.
const Domain kPrimary = Domain::from_extent({-200, 100}, {640, 480}, {33, 25});
const Domain kOther = Domain::from_extent({-237, 73}, {588, 448}, {22, 17});
const Domain kFarAway = Domain::from_extent({50000, 50000}, {588, 448}, {22, 17});

std::vector<const NodeType*> multi_raster_types() {
  std::vector<const NodeType*> out;
  for (const NodeType* t : NodeRegistry::instance().all()) {
    int rasters = 0;
    for (const auto& p : t->inputs) rasters += is_raster(p.type);
    if (rasters >= 2) out.push_back(t);
  }
  return out;
}

// Parameters under which every raster input is read (defaults otherwise).
std::map<std::string, ParamValue> params_for(const NodeType& t) {
  if (t.name == "PoissonDisk")  // density_1..3 serve classes 1..3; radii of metres keep the point count small
    return {{"class_count", std::int64_t{4}},
            {"radius_0", 20.0},
            {"radius_1", 16.0},
            {"radius_2", 12.0},
            {"radius_3", 10.0}};
  return {};
}

std::vector<std::string> serialized(const NodeRun& r) {
  std::vector<std::string> out;
  for (const auto& v : r.outputs) out.push_back(serialize_value(v));
  return out;
}

TEST(MismatchedGrids, TheTestSeesEveryFamily) {
  std::set<std::string> names;
  for (const NodeType* t : multi_raster_types()) names.insert(t->name);
  for (const char* expected :
       {"Add", "Blend", "Warp", "FBM", "Perlin", "ThermalErosion", "PipeErosion", "FlowAccumulation", "WaterFlow",
        "Biomes", "ResourceStack", "SplatWeights", "ColorByLayers", "HeightfieldToMesh", "ScatterRules", "PoissonDisk"})
    EXPECT_TRUE(names.count(expected)) << expected << " should have two or more raster inputs";
}

TEST(MismatchedGrids, SecondaryInputsAreResampledOntoThePrimary) {
  ASSERT_FALSE(domains_overlap(kPrimary, kFarAway));
  ASSERT_TRUE(domains_overlap(kPrimary, kOther));
  for (const NodeType* t : multi_raster_types()) {
    const PortDecl* primary = primary_port(*t);
    const auto base = inputs_on(*t, kPrimary);
    const auto params = params_for(*t);
    for (const auto& port : t->inputs) {
      if (!is_raster(port.type) || &port == primary) continue;
      SCOPED_TRACE(t->name + "." + port.name);
      auto shifted = base;
      shifted[port.name] = raster_on(port, kOther);
      NodeRun on_other;
      try {
        on_other = run_node(t->name, kPrimary, params, shifted);
      } catch (const std::exception& e) {
        ADD_FAILURE() << "fails on a secondary input on another grid: " << e.what();
        continue;
      }
      if (!samples_in_world_space(*t)) {
        auto explicit_inputs = base;
        explicit_inputs[port.name] = resampled_onto(shifted[port.name], kPrimary);
        EXPECT_EQ(serialized(on_other), serialized(run_node(t->name, kPrimary, params, explicit_inputs)))
            << "differs from feeding the input resampled onto the primary's domain";
      }
      auto far = base;
      far[port.name] = raster_on(port, kFarAway);
      try {
        run_node(t->name, kPrimary, params, far);
        ADD_FAILURE() << "runs with a secondary input that does not overlap the node's grid";
      } catch (const NodeError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(t->name + " '"), std::string::npos) << what;
        EXPECT_NE(what.find("input '" + port.name + "'"), std::string::npos) << what;
        EXPECT_NE(what.find("does not overlap the node's grid"), std::string::npos) << what;
      }
    }
  }
}

// Inputs already on the primary's domain are passed through, not copied: matching grids cost nothing and give
// the bits they gave before the rule.
TEST(MismatchedGrids, MatchingInputsAreNotCopied) {
  const HeightfieldPtr f = test::field_from(kPrimary, test::rolling_hills);
  EXPECT_EQ(match_domain(f, kPrimary).get(), f.get());
  const ImagePtr img = std::make_shared<Image>(kPrimary, 3);
  EXPECT_EQ(match_domain(img, kPrimary).get(), img.get());
  EXPECT_EQ(match_domain(HeightfieldPtr{}, kPrimary), nullptr);
}

TEST(MismatchedGrids, ImagesResampleEveryChannelLikeFields) {
  auto img = std::make_shared<Image>(kOther, 2);
  img->channel_names = {"u", "v"};
  Heightfield u(kOther), v(kOther);
  for (int j = 0; j < kOther.height(); ++j)
    for (int i = 0; i < kOther.width(); ++i) {
      u.at(i, j) = static_cast<float>(test::rolling_hills(kOther.x(i), kOther.y(j)));
      v.at(i, j) = static_cast<float>(kOther.x(i) - 2 * kOther.y(j));
      img->pixel(i, j)[0] = u.at(i, j);
      img->pixel(i, j)[1] = v.at(i, j);
    }
  const ImagePtr out = match_domain(ImagePtr(img), kPrimary);
  ASSERT_EQ(out->domain, kPrimary);
  EXPECT_EQ(out->channel_names, img->channel_names);
  const Heightfield ru = resample_bilinear(u, kPrimary), rv = resample_bilinear(v, kPrimary);
  for (int j = 0; j < kPrimary.height(); ++j)
    for (int i = 0; i < kPrimary.width(); ++i) {
      EXPECT_EQ(out->pixel(i, j)[0], ru.at(i, j));
      EXPECT_EQ(out->pixel(i, j)[1], rv.at(i, j));
    }
  // A plane is reproduced exactly where the primary lies inside the secondary (bilinear is exact on planes).
  const glm::dvec2 lo = kOther.min_corner(), hi = kOther.max_corner();
  for (int j = 0; j < kPrimary.height(); ++j)
    for (int i = 0; i < kPrimary.width(); ++i)
      if (kPrimary.x(i) >= lo.x && kPrimary.x(i) <= hi.x && kPrimary.y(j) >= lo.y && kPrimary.y(j) <= hi.y) {
        EXPECT_NEAR(out->pixel(i, j)[1], kPrimary.x(i) - 2 * kPrimary.y(j), 1e-3);
      }
}

TEST(MismatchedGrids, OverlapIsClosedAndTwoSided) {
  const Domain a = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  EXPECT_TRUE(domains_overlap(a, Domain::from_extent({100, 50}, {10, 10}, {2, 2}))) << "touching edges overlap";
  EXPECT_FALSE(domains_overlap(a, Domain::from_extent({100.5, 50}, {10, 10}, {2, 2})));
  EXPECT_FALSE(domains_overlap(a, Domain::from_extent({50, -20}, {10, 10}, {2, 2})));
  EXPECT_TRUE(domains_overlap(Domain::from_extent({40, 40}, {5, 5}, {2, 2}), a)) << "inside";
  EXPECT_TRUE(domains_overlap(a, Domain::from_extent({-50, -50}, {300, 300}, {4, 4}))) << "around";
}

TEST(MismatchedGrids, LibraryPreconditionNamesTheInput) {
  try {
    require_same_grid(kOther, kPrimary, "rainfall");
    FAIL() << "accepted another grid";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rainfall"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(require_same_grid(kPrimary, kPrimary, "rainfall"));
}

}  // namespace
}  // namespace orogen
