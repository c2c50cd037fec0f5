#include "graph/node_type.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "graph/file_text.h"
#include "graph/output_path.h"

namespace orogen {
namespace {

template <class List>
int index_of(const List& list, std::string_view n) {
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == n) return static_cast<int>(i);
  return -1;
}

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::string ParamDecl::check(const ParamValue& v) const {
  if (!holds_param_type(v, type)) return "expected a value of type " + std::string(to_string(type));
  auto check_number = [&](double x, const std::string& what) -> std::string {
    if (!std::isfinite(x)) return what + " must be a finite number";
    if (min && x < *min) return what + " " + format_number(x) + " is below the minimum " + format_number(*min);
    if (max && x > *max) return what + " " + format_number(x) + " is above the maximum " + format_number(*max);
    return {};
  };
  switch (type) {
    case ParamType::Float:
      return check_number(std::get<double>(v), "value");
    case ParamType::Int:
      return check_number(static_cast<double>(std::get<std::int64_t>(v)), "value");
    case ParamType::Vec2: {
      const auto& p = std::get<glm::dvec2>(v);
      for (int k = 0; k < 2; ++k)
        if (auto e = check_number(p[k], "component " + std::to_string(k)); !e.empty()) return e;
      return {};
    }
    case ParamType::Vec3: {
      const auto& p = std::get<glm::dvec3>(v);
      for (int k = 0; k < 3; ++k)
        if (auto e = check_number(p[k], "component " + std::to_string(k)); !e.empty()) return e;
      return {};
    }
    case ParamType::Color: {
      const auto& c = std::get<glm::vec4>(v);
      for (int k = 0; k < 4; ++k)
        if (!std::isfinite(c[k])) return "color components must be finite";
      return {};
    }
    case ParamType::Enum: {
      const auto& s = std::get<std::string>(v);
      if (std::find(choices.begin(), choices.end(), s) != choices.end()) return {};
      std::string all;
      for (const auto& c : choices) all += (all.empty() ? "" : ", ") + c;
      return "'" + s + "' is not one of: " + all;
    }
    case ParamType::Path: {
      const auto& s = std::get<std::string>(v);
      if (auto why = check_path_text(s); !why.empty()) return why;
      if (extensions.empty() || s.empty()) return {};
      for (const auto& ext : extensions) {
        if (s.size() >= ext.size()) {
          std::string tail = s.substr(s.size() - ext.size());
          std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char ch) { return std::tolower(ch); });
          if (tail == ext) return {};
        }
      }
      std::string all;
      for (const auto& e : extensions) all += (all.empty() ? "" : ", ") + e;
      return "file extension must be one of: " + all;
    }
    case ParamType::Curve: {
      const auto& c = std::get<CurveValue>(v);
      if (c.points.empty()) return "a curve needs at least one point";
      for (std::size_t i = 0; i < c.points.size(); ++i) {
        if (!std::isfinite(c.points[i].x) || !std::isfinite(c.points[i].y)) return "curve points must be finite";
        if (i > 0 && c.points[i].x <= c.points[i - 1].x) return "curve points must have strictly increasing x";
      }
      return {};
    }
    case ParamType::Gradient: {
      const auto& g = std::get<GradientValue>(v);
      if (g.stops.empty()) return "a gradient needs at least one stop";
      for (std::size_t i = 0; i < g.stops.size(); ++i) {
        if (!std::isfinite(g.stops[i].position)) return "gradient stop positions must be finite";
        if (i > 0 && g.stops[i].position < g.stops[i - 1].position) return "gradient stops must be sorted by position";
      }
      return {};
    }
    case ParamType::Table: {
      if (auto problem = check_table(table, std::get<TableValue>(v))) return problem->str(name);
      return {};
    }
    case ParamType::String:
      return file_text ? check_file_text(std::get<std::string>(v)) : std::string();
    case ParamType::Bool:
    case ParamType::Seed:
      return {};
  }
  return {};
}

const PortDecl* NodeType::find_input(std::string_view n) const {
  const int i = input_index(n);
  return i < 0 ? nullptr : &inputs[static_cast<std::size_t>(i)];
}
const PortDecl* NodeType::find_output(std::string_view n) const {
  const int i = output_index(n);
  return i < 0 ? nullptr : &outputs[static_cast<std::size_t>(i)];
}
const ParamDecl* NodeType::find_param(std::string_view n) const {
  const int i = param_index(n);
  return i < 0 ? nullptr : &params[static_cast<std::size_t>(i)];
}
int NodeType::input_index(std::string_view n) const { return index_of(inputs, n); }
int NodeType::output_index(std::string_view n) const { return index_of(outputs, n); }
int NodeType::param_index(std::string_view n) const { return index_of(params, n); }

NodeBuilder::Port& NodeBuilder::Port::description(std::string text) {
  list_[index_].description = std::move(text);
  return *this;
}
NodeBuilder::Port& NodeBuilder::Port::optional(bool value) {
  list_[index_].optional = value;
  return *this;
}
NodeBuilder::Port& NodeBuilder::Port::kind(OutputKind k) {
  list_[index_].kind = k;
  return *this;
}
NodeBuilder::Port& NodeBuilder::Port::unit(Unit u) {
  list_[index_].unit = u;
  return *this;
}
NodeBuilder::Port& NodeBuilder::Port::label(std::string text) {
  list_[index_].label = std::move(text);
  return *this;
}

std::string prettify_identifier(std::string_view identifier) {
  std::string label;
  for (const char c : identifier) label += c == '_' ? ' ' : c;
  if (!label.empty() && label[0] >= 'a' && label[0] <= 'z') label[0] = static_cast<char>(label[0] - 'a' + 'A');
  return label;
}

std::string_view to_string(OutputKind kind) {
  switch (kind) {
    case OutputKind::Auto:
      return "auto";
    case OutputKind::Height:
      return "height";
    case OutputKind::Mask:
      return "mask";
    case OutputKind::Signed:
      return "signed";
    case OutputKind::Scalar:
      return "scalar";
    case OutputKind::WaterDepth:
      return "water_depth";
  }
  return "auto";
}

ParamDecl& NodeBuilder::Param::decl() { return type_.params[index_]; }
NodeBuilder::Param& NodeBuilder::Param::range(double lo, double hi) {
  decl().min = lo;
  decl().max = hi;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::min(double lo) {
  decl().min = lo;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::max(double hi) {
  decl().max = hi;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::soft_range(double lo, double hi) {
  decl().soft_min = lo;
  decl().soft_max = hi;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::unit(Unit u) {
  decl().unit = u;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::label(std::string text) {
  decl().label = std::move(text);
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::description(std::string text) {
  decl().description = std::move(text);
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::extensions(std::vector<std::string> exts) {
  decl().extensions = std::move(exts);
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::output_file(bool value) {
  decl().output_file = value;
  return *this;
}
NodeBuilder::Param& NodeBuilder::Param::file_text(bool value) {
  decl().file_text = value;
  return *this;
}

NodeBuilder& NodeBuilder::category(std::string c) {
  type_.category = std::move(c);
  return *this;
}
NodeBuilder& NodeBuilder::description(std::string d) {
  type_.description = std::move(d);
  return *this;
}
NodeBuilder& NodeBuilder::version(int v) {
  type_.version = v;
  return *this;
}
NodeBuilder& NodeBuilder::domain_independent(bool value) {
  type_.domain_independent = value;
  return *this;
}
NodeBuilder& NodeBuilder::own_lattice(bool value) {
  type_.own_lattice = value;
  return *this;
}
NodeBuilder& NodeBuilder::writes_files(bool value) {
  type_.writes_files = value;
  return *this;
}
NodeBuilder& NodeBuilder::reach_pointwise() {
  type_.reach = Reach::pointwise();
  return *this;
}
NodeBuilder& NodeBuilder::reach_local(double metres, int samples) {
  type_.reach = Reach::local(metres, samples);
  return *this;
}
NodeBuilder& NodeBuilder::reach_global() {
  type_.reach = Reach::global();
  return *this;
}
NodeBuilder& NodeBuilder::reach(ReachFn fn, std::string summary) {
  type_.reach_fn = std::move(fn);
  type_.reach_summary = std::move(summary);
  return *this;
}
NodeBuilder& NodeBuilder::distribution(Distribution kind) {
  type_.distribution = kind;
  return *this;
}
NodeBuilder& NodeBuilder::distribution(DistributionFn fn, std::string summary) {
  type_.distribution_fn = std::move(fn);
  type_.distribution_summary = std::move(summary);
  return *this;
}
NodeBuilder& NodeBuilder::extra_bytes(CostFn fn) {
  type_.extra_bytes = std::move(fn);
  return *this;
}
void NodeBuilder::execute(ExecuteFn fn) { type_.execute = std::move(fn); }

const char* to_string(ReachKind kind) {
  switch (kind) {
    case ReachKind::Pointwise:
      return "pointwise";
    case ReachKind::Local:
      return "local";
    case ReachKind::Global:
      return "global";
    case ReachKind::Undeclared:
      break;
  }
  return "undeclared";
}

glm::ivec2 Reach::halo(glm::dvec2 spacing) const {
  switch (kind) {
    case ReachKind::Pointwise:
      return {0, 0};
    case ReachKind::Local: {
      const auto axis = [&](double s) {
        // The small tolerance keeps 40 m on a 10 m lattice at 4 samples, not 5 from rounding in the division.
        return static_cast<int>(std::ceil(metres / s - 1e-9)) + samples;
      };
      return {axis(spacing.x), axis(spacing.y)};
    }
    case ReachKind::Global:
    case ReachKind::Undeclared:
      break;
  }
  return {-1, -1};
}

std::string Reach::describe() const {
  switch (kind) {
    case ReachKind::Pointwise:
      return "point-wise";
    case ReachKind::Local: {
      std::string s = "local: ";
      if (metres > 0.0) s += format_number(metres) + " m";
      if (samples > 0)
        s += std::string(metres > 0.0 ? " + " : "") + std::to_string(samples) + (samples == 1 ? " sample" : " samples");
      if (metres <= 0.0 && samples <= 0) s += "0";
      return s;
    }
    case ReachKind::Global:
      return "global";
    case ReachKind::Undeclared:
      break;
  }
  return "undeclared";
}

const ParamValue& ParamView::value(std::string_view name) const {
  const int k = type_.param_index(name);
  if (k < 0 || static_cast<std::size_t>(k) >= values_.size())
    throw std::out_of_range("node type '" + type_.name + "' has no parameter '" + std::string(name) + "'");
  return values_[static_cast<std::size_t>(k)];
}

Reach NodeType::reach_for(const std::vector<ParamValue>& params) const {
  if (!reach_fn) return reach;
  return reach_fn(ParamView(*this, params));
}

std::string NodeType::reach_text() const { return reach_fn ? reach_summary : reach.describe(); }

Distribution NodeType::distribution_for(const std::vector<ParamValue>& params) const {
  if (!reach_for(params).is_global()) return Distribution::PerTile;
  if (distribution_fn) return distribution_fn(ParamView(*this, params));
  if (distribution != Distribution::Undeclared) return distribution;
  if (writes_files) return Distribution::PerTile;
  if (domain_independent) return Distribution::Replicated;
  return Distribution::Undeclared;
}

NodeBuilder::Port NodeBuilder::input(std::string name, PortType type) {
  type_.inputs.push_back({std::move(name), type, {}, false});
  return Port(type_.inputs, type_.inputs.size() - 1);
}
NodeBuilder::Port NodeBuilder::output(std::string name, PortType type) {
  type_.outputs.push_back({std::move(name), type, {}, false});
  return Port(type_.outputs, type_.outputs.size() - 1);
}

NodeBuilder::Param NodeBuilder::add_param(std::string name, ParamType type, ParamValue def) {
  ParamDecl d;
  d.name = std::move(name);
  d.type = type;
  d.default_value = std::move(def);
  type_.params.push_back(std::move(d));
  return Param(type_, type_.params.size() - 1);
}
NodeBuilder::Param NodeBuilder::param_float(std::string name, double def) {
  return add_param(std::move(name), ParamType::Float, def);
}
NodeBuilder::Param NodeBuilder::param_int(std::string name, std::int64_t def) {
  return add_param(std::move(name), ParamType::Int, def);
}
NodeBuilder::Param NodeBuilder::param_bool(std::string name, bool def) {
  return add_param(std::move(name), ParamType::Bool, def);
}
NodeBuilder::Param NodeBuilder::param_vec2(std::string name, glm::dvec2 def) {
  return add_param(std::move(name), ParamType::Vec2, def);
}
NodeBuilder::Param NodeBuilder::param_vec3(std::string name, glm::dvec3 def) {
  return add_param(std::move(name), ParamType::Vec3, def);
}
NodeBuilder::Param NodeBuilder::param_color(std::string name, glm::vec4 def) {
  return add_param(std::move(name), ParamType::Color, def);
}
NodeBuilder::Param NodeBuilder::param_enum(std::string name, std::vector<std::string> choices, std::string def) {
  auto p = add_param(std::move(name), ParamType::Enum, std::move(def));
  type_.params.back().choices = std::move(choices);
  return p;
}
NodeBuilder::Param NodeBuilder::param_string(std::string name, std::string def) {
  return add_param(std::move(name), ParamType::String, std::move(def));
}
NodeBuilder::Param NodeBuilder::param_path(std::string name, std::string def) {
  return add_param(std::move(name), ParamType::Path, std::move(def));
}
NodeBuilder::Param NodeBuilder::param_seed(std::string name, std::uint64_t def) {
  return add_param(std::move(name), ParamType::Seed, def);
}
NodeBuilder::Param NodeBuilder::param_curve(std::string name, CurveValue def) {
  return add_param(std::move(name), ParamType::Curve, std::move(def));
}
NodeBuilder::Param NodeBuilder::param_gradient(std::string name, GradientValue def) {
  return add_param(std::move(name), ParamType::Gradient, std::move(def));
}
NodeBuilder::Param NodeBuilder::param_table(std::string name, TableSchema schema, TableValue def) {
  Param p = add_param(std::move(name), ParamType::Table, std::move(def));
  type_.params.back().table = std::move(schema);
  return p;
}

void check_declaration(const NodeType& type) {
  auto fail = [&](const std::string& why) { throw std::logic_error("node type '" + type.name + "': " + why); };
  if (type.name.empty()) fail("empty name");
  if (type.category.empty()) fail("no category");
  if (type.description.empty()) fail("no description");
  if (!type.execute) fail("no execute function");
  if (type.reach_fn && type.reach_summary.empty()) fail("a reach function needs a summary for the node reference");
  if (type.distribution_fn && type.distribution_summary.empty())
    fail("a distribution function needs a summary for the node reference");
  if (type.can_be_global() && type.distribution == Distribution::Undeclared && !type.distribution_fn &&
      !type.writes_files && !type.domain_independent)
    fail(
        "its reach can be global, so it must declare how it runs across ranks: b.distribution(Distribution::...) "
        "(graph/distribution.h)");
  if (type.reach.kind == ReachKind::Local &&
      (!(type.reach.metres >= 0.0) || !std::isfinite(type.reach.metres) || type.reach.samples < 0))
    fail("a local reach needs a finite radius >= 0");
  std::set<std::string> names;
  for (const auto& p : type.inputs)
    if (!names.insert("in:" + p.name).second) fail("duplicate input '" + p.name + "'");
  for (const auto& p : type.outputs) {
    if (!names.insert("out:" + p.name).second) fail("duplicate output '" + p.name + "'");
    if (p.kind != OutputKind::Auto && p.type != PortType::Heightfield)
      fail("output '" + p.name + "' declares a kind but is not a heightfield");
  }
  for (const auto& p : type.inputs)
    if (p.kind != OutputKind::Auto) fail("input '" + p.name + "' declares a kind (outputs only)");
  for (const auto& p : type.params) {
    if (!names.insert("param:" + p.name).second) fail("duplicate parameter '" + p.name + "'");
    if (p.description.empty()) fail("parameter '" + p.name + "' has no description");
    if (auto why = p.check(p.default_value); !why.empty()) fail("default of '" + p.name + "': " + why);
    if (p.type != ParamType::Table) continue;
    if (p.table.columns.empty()) fail("table '" + p.name + "' has no columns");
    std::set<std::string> columns;
    for (const auto& c : p.table.columns) {
      if (c.name.empty() || !columns.insert(c.name).second)
        fail("table '" + p.name + "': empty or duplicate column name");
      if (c.description.empty()) fail("table '" + p.name + "': column '" + c.name + "' has no description");
      if (c.type == ColumnType::Enum && c.choices.empty()) fail("table '" + p.name + "': enum column without choices");
    }
  }
  if (type.outputs.empty() && !type.writes_files) fail("no outputs and writes no files");
}

}  // namespace orogen
