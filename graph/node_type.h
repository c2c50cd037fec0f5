#pragma once
// A node type: documented typed ports and parameters plus the function that evaluates it.
// Declared in one place beside its algorithm with OROGEN_NODE (see registry.h), in the style of Blender's
// geometry-node declarations:
//
//   OROGEN_NODE(Add) {
//     b.category("field").description("Sum of two fields.");
//     b.input("a", PortType::Heightfield).description("First field");
//     b.output("out", PortType::Heightfield);
//     b.param_float("scale", 1.0).range(-1e3, 1e3).unit(Unit::Factor).description("Multiplier of b");
//     b.execute([](ExecContext& ctx) { ... });
//   }
#include <functional>
#include <optional>
#include <variant>
#include <string>
#include <string_view>
#include <vector>

#include "graph/distribution.h"
#include "graph/param_value.h"
#include "graph/units.h"
#include "graph/value_type.h"

namespace orogen {

class ExecContext;

// What a heightfield output holds, so viewers choose a colour map and range without guessing: terrain
// heights (m), masks in 0..1, signed fields centred on 0 (curvature, differences, northness), non-negative
// quantities (slope angle, flow), water depth (m; 0 = dry). Auto: inferred by the viewer (a port named like a
// mask is a mask, an operator passes on the kind of its primary input, anything else is a height).
enum class OutputKind { Auto, Height, Mask, Signed, Scalar, WaterDepth };
std::string_view to_string(OutputKind kind);

// An identifier (`sun_azimuth`) as a display label (`Sun azimuth`): words split at underscores, the first
// capitalized.
std::string prettify_identifier(std::string_view identifier);

// Ports and parameters have a stable identifier (`name`: graph files, links, --set) and a display label the
// editor and `orogen nodes` show (Blender's split): a label can change without a graph-format migration.
struct PortDecl {
  std::string name;
  PortType type = PortType::Heightfield;
  std::string description;
  bool optional = false;               // inputs only: may stay unconnected
  OutputKind kind = OutputKind::Auto;  // heightfield outputs only: what the values mean (for viewers)
  Unit unit = Unit::None;              // what the values are in, where one unit holds (heights m, masks unitless)
  std::string label;                   // empty: prettify_identifier(name)
  std::string display_label() const { return label.empty() ? prettify_identifier(name) : label; }
};

struct ParamDecl {
  std::string name;
  ParamType type = ParamType::Float;
  ParamValue default_value;
  // Hard bounds, checked on load and on edit (numbers, and each component of vectors).
  std::optional<double> min, max;
  // Suggested slider range for the editor; defaults to the hard bounds.
  std::optional<double> soft_min, soft_max;
  Unit unit = Unit::None;  // every number has one (tests/test_registry_conventions.cpp)
  std::string description;
  std::vector<std::string> choices;     // Enum: allowed values
  bool output_file = false;             // Path: a file this node writes (resolved inside the output directory)
  std::vector<std::string> extensions;  // Path: accepted file extensions, e.g. {".exr", ".png"}
  bool file_text = false;               // String: written into an output file, so one printable line
  TableSchema table;                    // Table: the columns and row bounds
  std::string label;                    // empty: prettify_identifier(name)

  std::string display_label() const { return label.empty() ? prettify_identifier(name) : label; }
  // Empty if `v` is a valid value for this parameter, else why not (tables: "name[row].column: why").
  std::string check(const ParamValue& v) const;
};

struct NodeType;
struct SubgraphAsset;
using ExecuteFn = std::function<void(ExecContext&)>;

// How far a node's output at one sample depends on its inputs: the tiled build's halos, and the nodes it
// cannot tile.
//  - point-wise: the output at a sample depends only on the inputs at that sample (and on its world
//    position);
//  - local: on the inputs within `metres` + `samples` sample spacings of it (per axis);
//  - global: on the whole domain (normalization over the domain, simulations, flow, meshes, writers).
// A non-global node evaluated on a sub-domain expanded by its halo reproduces the full-domain result inside
// the sub-domain bit for bit (tests/test_node_reach.cpp). Undeclared is the default, so a node that forgets
// to declare fails that test.
enum class ReachKind { Undeclared, Pointwise, Local, Global };

struct Reach {
  ReachKind kind = ReachKind::Undeclared;
  double metres = 0.0;  // local: radius in metres ...
  int samples = 0;      // ... plus this many samples

  static Reach pointwise() { return {ReachKind::Pointwise, 0.0, 0}; }
  static Reach local(double metres, int samples = 0) { return {ReachKind::Local, metres, samples}; }
  static Reach global() { return {ReachKind::Global, 0.0, 0}; }

  bool is_global() const { return kind == ReachKind::Global || kind == ReachKind::Undeclared; }
  // The halo in samples along x and y on a lattice of `spacing`: ceil(metres / spacing) + samples; 0 for
  // point-wise, -1 for global or undeclared.
  glm::ivec2 halo(glm::dvec2 spacing) const;
  // "point-wise", "local: 40 m + 2 samples", "global", "undeclared".
  std::string describe() const;
};

const char* to_string(ReachKind kind);  // "pointwise", "local", "global", "undeclared"

// Effective parameter values of a node by name, for reach functions.
class ParamView {
 public:
  ParamView(const NodeType& type, const std::vector<ParamValue>& values) : type_(type), values_(values) {}
  template <class T>
  const T& get(std::string_view name) const {
    return std::get<T>(value(name));
  }
  const ParamValue& value(std::string_view name) const;  // throws std::out_of_range for an unknown name
 private:
  const NodeType& type_;
  const std::vector<ParamValue>& values_;
};

// A reach that depends on parameter values (Blur's sigma, Normalize's range mode, ...).
using ReachFn = std::function<Reach(const ParamView&)>;
// A distribution that depends on parameter values (PoissonDisk is tile invariant only without fill_border).
using DistributionFn = std::function<Distribution(const ParamView&)>;

// Bytes a node needs beyond the default estimate (graph/cost_query.h).
struct CostQuery;
using CostFn = std::function<std::uint64_t(const CostQuery&)>;

struct NodeType {
  std::string name;
  std::string category;
  std::string description;
  int version = 1;
  // The node library (graph/node_library.h) the type comes from; empty for the types built into Orogen.
  std::string library;
  std::vector<PortDecl> inputs;
  std::vector<PortDecl> outputs;
  std::vector<ParamDecl> params;
  ExecuteFn execute;
  // The result does not depend on the requested domain (meshes of rocks, L-system strings): the domain is
  // left out of the cache key so preview and build share the result.
  bool domain_independent = false;
  // The node's raster outputs lie on a lattice of its own (Resample), not on the requested domain's: a tiled
  // build cannot cut a whole-domain result of it into tiles, so it evaluates the node per tile.
  bool own_lattice = false;
  // The node writes files (writers): it is evaluated for its side effect and its cached result is only
  // trusted while the files it wrote are still there unchanged.
  bool writes_files = false;
  // The reach (see Reach): fixed, or computed from the parameters by reach_fn when that is set, in which
  // case `reach_summary` says how ("local: 5.2 sigma + 2 samples").
  Reach reach;
  ReachFn reach_fn;
  std::string reach_summary;
  // How the node runs across ranks when its reach is global (graph/distribution.h); derived otherwise. Fixed, or
  // computed from the parameters by distribution_fn when that is set, `distribution_summary` saying how.
  Distribution distribution = Distribution::Undeclared;
  DistributionFn distribution_fn;
  std::string distribution_summary;
  // Memory beyond the default estimate (outputs by type at the domain's sample count), when the node knows it
  // needs more: see graph/cost_query.h and evaluator/memory_estimate.h.
  CostFn extra_bytes;
  // Set for the type of a subgraph instance (graph/subgraph.h): the asset whose interface it presents. Such
  // nodes are expanded into the asset's nodes before evaluation; they never run themselves.
  const SubgraphAsset* subgraph = nullptr;

  // The reach for these effective parameter values (declaration order, as Graph::effective_params).
  Reach reach_for(const std::vector<ParamValue>& params) const;
  // How the reach reads in the node reference: the fixed reach, or the summary of the function.
  std::string reach_text() const;
  // How the node runs in a distributed build with these parameter values: per tile when the reach is point-wise
  // or local, else the declared kind; undeclared ones default to per tile for writers and to replicated for
  // domain-independent nodes.
  Distribution distribution_for(const std::vector<ParamValue>& params) const;
  // Whether some parameter values can make the reach global (a global reach, or a reach function).
  bool can_be_global() const { return reach_fn || reach.kind == ReachKind::Global; }

  const PortDecl* find_input(std::string_view n) const;
  const PortDecl* find_output(std::string_view n) const;
  const ParamDecl* find_param(std::string_view n) const;
  int input_index(std::string_view n) const;   // -1 if absent
  int output_index(std::string_view n) const;  // -1 if absent
  int param_index(std::string_view n) const;   // -1 if absent
};

// Fluent declaration of a NodeType. Port and parameter builders refer to entries by index, so they stay
// valid while more entries are added.
class NodeBuilder {
 public:
  class Port {
   public:
    Port(std::vector<PortDecl>& list, std::size_t index) : list_(list), index_(index) {}
    Port& description(std::string text);
    Port& optional(bool value = true);
    Port& kind(OutputKind k);
    Port& unit(Unit u);
    Port& label(std::string text);

   private:
    std::vector<PortDecl>& list_;
    std::size_t index_;
  };
  class Param {
   public:
    Param(NodeType& type, std::size_t index) : type_(type), index_(index) {}
    Param& range(double lo, double hi);
    Param& min(double lo);
    Param& max(double hi);
    Param& soft_range(double lo, double hi);
    Param& unit(Unit u);
    Param& label(std::string text);
    Param& description(std::string text);
    Param& extensions(std::vector<std::string> exts);
    Param& output_file(bool value = true);
    Param& file_text(bool value = true);

   private:
    ParamDecl& decl();
    NodeType& type_;
    std::size_t index_;
  };

  explicit NodeBuilder(NodeType& type) : type_(type) {}

  NodeBuilder& category(std::string c);
  NodeBuilder& description(std::string d);
  NodeBuilder& version(int v);
  NodeBuilder& domain_independent(bool value = true);
  NodeBuilder& own_lattice(bool value = true);
  NodeBuilder& writes_files(bool value = true);
  // Reach declarations; exactly one per node type.
  NodeBuilder& reach_pointwise();
  NodeBuilder& reach_local(double metres, int samples = 0);
  NodeBuilder& reach_global();
  NodeBuilder& reach(ReachFn fn, std::string summary);
  // How the node runs across ranks (graph/distribution.h); required when the reach can be global.
  NodeBuilder& distribution(Distribution kind);
  NodeBuilder& distribution(DistributionFn fn, std::string summary);
  // Memory the node needs beyond the default estimate (see NodeType::extra_bytes).
  NodeBuilder& extra_bytes(CostFn fn);
  void execute(ExecuteFn fn);

  Port input(std::string name, PortType type);
  Port output(std::string name, PortType type);

  Param param_float(std::string name, double def);
  Param param_int(std::string name, std::int64_t def);
  Param param_bool(std::string name, bool def);
  Param param_vec2(std::string name, glm::dvec2 def);
  Param param_vec3(std::string name, glm::dvec3 def);
  Param param_color(std::string name, glm::vec4 def);
  Param param_enum(std::string name, std::vector<std::string> choices, std::string def);
  Param param_string(std::string name, std::string def);
  Param param_path(std::string name, std::string def);
  Param param_seed(std::string name = "seed", std::uint64_t def = 0);
  Param param_curve(std::string name, CurveValue def);
  Param param_gradient(std::string name, GradientValue def);
  // A table of rows under `schema` (graph/table_value.h); the default must satisfy it.
  Param param_table(std::string name, TableSchema schema, TableValue def);

 private:
  Param add_param(std::string name, ParamType type, ParamValue def);
  NodeType& type_;
};

// Throws std::logic_error describing the first inconsistency (duplicate names, default out of range, enum
// default not among the choices, no execute function, ...). Run at registration.
void check_declaration(const NodeType& type);

}  // namespace orogen
