// The contracts that run the node (testing/contracts.h): the tile contract of the declared reach, and
// determinism across thread counts; plus the declaration's consistency and the list of every contract.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

#include <tbb/task_arena.h>

#include "evaluator/run_node.h"
#include "evaluator/value_serialization.h"
#include "graph/curves.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/polygon_map.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/hash.h"
#include "testing/contracts.h"

namespace orogen::contracts {
namespace {

// Per-sample detail in [-0.5, 0.5) hashed from the global lattice index: every sample differs from its
// neighbours, so a halo that is too small shows.
double detail(const Domain& d, int i, int j) {
  const auto a = static_cast<std::uint64_t>(std::int64_t{d.first.x} + i);
  const auto b = static_cast<std::uint64_t>(std::int64_t{d.first.y} + j);
  return unit_double(mix64(a * kGoldenGamma + b + 0x632BE59BD9B4E019ull)) - 0.5;
}

// Smooth terrain-like heights in metres (a few hundred metres of relief over kilometres).
double rolling_hills(double x, double y) {
  return 220.0 * std::sin(x / 310.0) * std::cos(y / 270.0) + 90.0 * std::sin((x + 2.0 * y) / 530.0) + 0.05 * x + 40.0;
}

// Curves and polygon maps in fixed world coordinates (the same for every domain) over the region the reach
// domains cover: x in about [-1300, 0], y in about [500, 1600].
PortValue fixed_curves() {
  static const CurvesPtr curves = [] {
    auto c = std::make_shared<Curves>();
    for (int k = 0; k < 4; ++k) {
      Curve curve;
      for (int i = 0; i <= 40; ++i) {
        const double t = i / 40.0;
        curve.points.emplace_back(static_cast<float>(-1400.0 + 1500.0 * t),
                                  static_cast<float>(450.0 + 300.0 * k + 120.0 * std::sin(7.0 * t + k)),
                                  static_cast<float>(50.0 * (1.0 - t) + 3.0 * k));
        curve.width.push_back(static_cast<float>(6.0 + 4.0 * k));
      }
      c->curves.push_back(std::move(curve));
    }
    return c;
  }();
  return PortValue(curves);
}

PortValue fixed_polygon_map() {
  if (!NodeRegistry::instance().find("VoronoiIsland")) return {};
  static const PolygonMapPtr map = run_node("VoronoiIsland", Domain::from_extent({0, 0}, {1, 1}, {2, 2}),
                                            {{"min_corner", glm::dvec2(-1500, 300)},
                                             {"size", glm::dvec2(1700, 1500)},
                                             {"cells", std::int64_t{300}},
                                             {"shape_scale", 1.0}})
                                       .get<PolygonMap>(0);
  return PortValue(map);
}

// The w x h samples at (i0, j0) of an output, as floats (all channels of images; a report's text). Empty
// for an output that has no samples.
std::vector<float> crop(const PortValue& v, int i0, int j0, int w, int h) {
  std::vector<float> out;
  if (const auto* f = std::get_if<HeightfieldPtr>(&v)) {
    for (int j = j0; j < j0 + h; ++j)
      for (int i = i0; i < i0 + w; ++i) out.push_back((*f)->at(i, j));
  } else if (const auto* img = std::get_if<ImagePtr>(&v)) {
    for (int j = j0; j < j0 + h; ++j)
      for (int i = i0; i < i0 + w; ++i)
        for (int c = 0; c < (*img)->channels; ++c) out.push_back((*img)->pixel(i, j)[c]);
  } else if (const auto* rep = std::get_if<ReportPtr>(&v)) {
    // A report describes the node's settings, not samples (Biomes' table): it must not change either.
    for (char ch : (*rep)->json) out.push_back(static_cast<float>(ch));
  }
  return out;
}

bool bit_identical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                            [](float x, float y) { return std::memcmp(&x, &y, sizeof(float)) == 0; });
}

// The first sample (column, row) where two crops differ, for the message.
std::string first_difference(const std::vector<float>& a, const std::vector<float>& b, int w, int channels) {
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k)
    if (std::memcmp(&a[k], &b[k], sizeof(float)) != 0) {
      const auto sample = static_cast<int>(k) / channels;
      return "first at sample (" + std::to_string(sample % w) + ", " + std::to_string(sample / w) +
             ") of the sub-domain: " + std::to_string(a[k]) + " whole vs " + std::to_string(b[k]) + " tiled";
    }
  return "the sizes differ";
}

std::vector<ParamValue> effective(const NodeType& t, const std::map<std::string, ParamValue>& given) {
  std::vector<ParamValue> v;
  for (const auto& p : t.params) {
    const auto it = given.find(p.name);
    v.push_back(it != given.end() ? it->second : p.default_value);
  }
  return v;
}

// Generated inputs for every port, or the name of a port the kit cannot make one for.
std::string make_inputs(const NodeType& t, const Domain& d, std::map<std::string, PortValue>& inputs) {
  for (const auto& port : t.inputs) {
    auto v = contract_input(port, d);
    if (std::holds_alternative<std::monostate>(v)) return port.name + " (" + std::string(to_string(port.type)) + ")";
    inputs[port.name] = std::move(v);
  }
  return {};
}

std::string label(const NodeType& t, const ParamCase& c) { return t.name + " (" + c.label + ")"; }

}  // namespace

std::vector<ParamCase> param_cases(const NodeType& type) {
  std::vector<ParamCase> out{{{}, "defaults"}};
  for (const auto& p : type.params)
    for (const auto& c : p.choices)
      if (c != std::get<std::string>(p.default_value)) out.push_back({{{p.name, c}}, p.name + "=" + c});
  return out;
}

PortValue contract_input(const PortDecl& port, const Domain& d) {
  if (port.type == PortType::Curves) return fixed_curves();
  if (port.type == PortType::PolygonMap) return fixed_polygon_map();
  if (port.type == PortType::Image) {  // 12 channels (monthly climate images, layer weights): smooth plus detail
    auto img = std::make_shared<Image>(d, 12);
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i)
        for (int c = 0; c < 12; ++c)
          img->pixel(i, j)[c] = static_cast<float>(0.5 + 0.3 * std::sin(d.x(i) / (150.0 + 10 * c) + d.y(j) / 210.0) +
                                                   0.1 * detail(d, i, j));
    return PortValue(ImagePtr(img));
  }
  if (port.type != PortType::Heightfield) return {};
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const double x = d.x(i), y = d.y(j), n = detail(d, i, j);
      double v;
      if (port.name == "mask" || port.name == "roughness" || port.name == "amplitude")
        v = 0.5 + 0.4 * std::sin(x / 170.0 + y / 230.0) + 0.1 * n;  // 0..1
      else if (port.name == "dx" || port.name == "dy" || port.name == "warp_x" || port.name == "warp_y" ||
               port.name == "distance_offset")
        v = 30.0 * std::sin((port.name.back() == 'y' ? x : y) / 140.0) + 5.0 * n;  // metres of displacement
      else
        v = rolling_hills(x, y) + 8.0 * n;  // heights in metres
      h->at(i, j) = static_cast<float>(v);
    }
  return PortValue(HeightfieldPtr(h));
}

ContractResult check_reach(const NodeType& type, const ParamCase& c) {
  ContractResult r{"reach", Status::Passed, {}, ""};
  const Reach reach = type.reach_for(effective(type, c.params));
  if (reach.kind == ReachKind::Undeclared) {
    r.status = Status::Failed;
    r.failures.push_back(label(type, c) +
                         " declares no reach: call b.reach_pointwise(), reach_local(metres, "
                         "samples), reach_global() or reach(fn, summary) in its declaration");
    return r;
  }
  if (reach.is_global() || type.writes_files) {
    r.status = Status::Skipped;
    r.note = "global reach: evaluated whole, never tiled";
    return r;
  }
  // The full domain, the sub-domain and its expansion by the halo, on a 10 m x 8 m lattice: anisotropic
  // spacing, an odd origin, and a margin beyond the expansion so the full domain's own edges are out of reach.
  const glm::ivec2 halo = reach.halo({10.0, 8.0});
  const glm::ivec2 size{40, 30}, margin{9, 7};
  const glm::ivec2 res = size + 2 * (halo + margin);
  if (res.x > 4096 || res.y > 4096) {
    r.status = Status::Skipped;
    r.note = "halo of " + std::to_string(halo.x) + " samples is too large to check on a small domain";
    return r;
  }
  const Domain full = Domain::from_extent({-1234.5, 567.25}, {10.0 * (res.x - 1), 8.0 * (res.y - 1)}, res);
  const glm::ivec2 sub_at = halo + margin;
  const Domain expanded = full.subdomain(margin.x, margin.y, size.x + 2 * halo.x, size.y + 2 * halo.y);
  std::map<std::string, PortValue> in_full, in_part;
  if (const auto missing = make_inputs(type, full, in_full); !missing.empty()) {
    r.status = Status::Skipped;
    r.note = "the kit cannot generate input " + missing;
    return r;
  }
  make_inputs(type, expanded, in_part);
  NodeRun a, b;
  try {
    a = run_node(type.name, full, c.params, in_full);
    b = run_node(type.name, expanded, c.params, in_part);
  } catch (const std::exception& e) {
    r.status = Status::Failed;
    r.failures.push_back(label(type, c) + " failed on the reach check's domain: " + e.what());
    return r;
  } catch (...) {  // a node library may throw anything; the table must still be printed
    r.status = Status::Failed;
    r.failures.push_back(label(type, c) + " threw something that is not a std::exception");
    return r;
  }
  r.note = "reach " + reach.describe();
  for (std::size_t k = 0; k < a.outputs.size() && k < b.outputs.size(); ++k) {
    const auto whole = crop(a.outputs[k], sub_at.x, sub_at.y, size.x, size.y);
    const auto tiled = crop(b.outputs[k], halo.x, halo.y, size.x, size.y);
    if (whole.empty()) {
      r.failures.push_back(label(type, c) + ": output '" + type.outputs[k].name +
                           "' has no samples (not a field or an image), so the node cannot be tiled: declare "
                           "b.reach_global()");
      continue;
    }
    if (!bit_identical(whole, tiled)) {
      const int channels = static_cast<int>(whole.size() / static_cast<std::size_t>(size.x * size.y));
      r.failures.push_back(label(type, c) + ": output '" + type.outputs[k].name +
                           "' on a sub-domain expanded by the declared halo (" + reach.describe() + ": " +
                           std::to_string(halo.x) + "x" + std::to_string(halo.y) +
                           " samples) differs from the whole domain's (" +
                           first_difference(whole, tiled, size.x, std::max(channels, 1)) +
                           "): the declared reach is too small for what the node reads");
    }
  }
  if (!r.failures.empty()) r.status = Status::Failed;
  return r;
}

ContractResult check_threads(const NodeType& type, const ParamCase& c, const Domain& d, int threads) {
  ContractResult r{"threads", Status::Passed, {}, "1 and " + std::to_string(threads) + " threads"};
  if (type.writes_files) {
    r.status = Status::Skipped;
    r.note = "writes files";
    return r;
  }
  std::map<std::string, PortValue> inputs;
  if (const auto missing = make_inputs(type, d, inputs); !missing.empty()) {
    r.status = Status::Skipped;
    r.note = "the kit cannot generate input " + missing;
    return r;
  }
  auto run = [&](int n) {
    tbb::task_arena arena(n);
    return arena.execute([&] { return run_node(type.name, d, c.params, inputs); });
  };
  NodeRun one, many;
  try {
    one = run(1);
    many = run(threads);
  } catch (const std::exception& e) {
    r.status = Status::Skipped;
    r.note = std::string("the node fails on the generated inputs: ") + e.what();
    return r;
  } catch (...) {
    r.status = Status::Failed;
    r.failures.push_back(label(type, c) + " threw something that is not a std::exception");
    return r;
  }
  for (std::size_t k = 0; k < one.outputs.size() && k < many.outputs.size(); ++k)
    if (serialize_value(one.outputs[k]) != serialize_value(many.outputs[k]))
      r.failures.push_back(label(type, c) + ": output '" + type.outputs[k].name + "' with 1 thread differs from " +
                           std::to_string(threads) +
                           " threads: the result depends on how the work is split (a reduction or a random stream "
                           "per thread or chunk?); split by rows or blocks of the domain, never by thread count");
  if (!r.failures.empty()) r.status = Status::Failed;
  return r;
}

ContractResult check_declaration_contract(const NodeType& type) {
  ContractResult r{"declaration", Status::Passed, {}, "descriptions, units, ranges, reach"};
  auto fail = [&](std::string why) { r.failures.push_back(type.name + ": " + std::move(why)); };
  if (type.description.size() < 20) fail("the node's description is missing or too short to say what it computes");
  if (type.category.empty()) fail("no category (b.category(...)): the palette groups nodes by it");
  if (type.reach_for(effective(type, {})).kind == ReachKind::Undeclared) fail("no reach declared");
  for (const auto* ports : {&type.inputs, &type.outputs})
    for (const auto& p : *ports)
      if (p.description.empty()) fail("port '" + p.name + "' has no description");
  for (const auto& p : type.params) {
    if (p.description.empty()) fail("parameter '" + p.name + "' has no description");
    const bool number = p.type == ParamType::Float || p.type == ParamType::Int || p.type == ParamType::Vec2 ||
                        p.type == ParamType::Vec3;
    if (!number) continue;
    if (p.unit == Unit::None)
      fail("parameter '" + p.name + "' has no unit (.unit(Unit::...); Unit::Unitless for a pure number)");
    if (!p.min || !p.max)
      fail("parameter '" + p.name + "' has no hard range (.range(lo, hi)): extreme values reach the algorithm");
    if (p.soft_min && p.min && *p.soft_min < *p.min)
      fail("parameter '" + p.name + "': its soft range starts below its hard range");
    if (p.soft_max && p.max && *p.soft_max > *p.max)
      fail("parameter '" + p.name + "': its soft range ends above its hard range");
  }
  if (!r.failures.empty()) r.status = Status::Failed;
  return r;
}

std::vector<ContractResult> check_node_contracts(const NodeType& type, unsigned contracts) {
  const Domain key_domain = Domain::from_extent({-300.0, 200.0}, {480.0, 384.0}, {16, 13});
  const Domain run_domain = Domain::from_extent({-1234.5, 567.25}, {630.0, 376.0}, {64, 48});
  // More than one thread, as many as the machine has up to 4 (more arena slots than cores only warns).
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 2u, 4u));
  std::vector<ContractResult> out;
  if (contracts & kDeclarationContract) out.push_back(check_declaration_contract(type));
  if (contracts & kCacheKeyContract) out.push_back(check_cache_key(type, key_domain));
  // Reach and threads over every case, folded into one row each.
  for (const unsigned which : {unsigned{kReachContract}, unsigned{kThreadsContract}}) {
    if (!(contracts & which)) continue;
    ContractResult row{which == kReachContract ? "reach" : "threads", Status::Skipped, {}, ""};
    for (const auto& c : param_cases(type)) {
      auto one = which == kReachContract ? check_reach(type, c) : check_threads(type, c, run_domain, threads);
      if (one.status != Status::Skipped && row.status == Status::Skipped) row.status = Status::Passed;
      if (one.status == Status::Failed) row.status = Status::Failed;
      if (row.note.empty() || one.status != Status::Skipped) row.note = one.note;
      for (auto& f : one.failures) row.failures.push_back(std::move(f));
    }
    out.push_back(std::move(row));
  }
  if (contracts & kExtremesContract) out.push_back(check_extremes(type));
  return out;
}

}  // namespace orogen::contracts
