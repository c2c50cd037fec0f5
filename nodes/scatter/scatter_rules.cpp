#include "nodes/scatter/scatter_rules.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "graph/table_json.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/smoothstep.h"
#include "nodes/common/work_poll.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::quat yaw(double angle) { return glm::angleAxis(static_cast<float>(angle), glm::vec3(0.0f, 0.0f, 1.0f)); }

}  // namespace

TableSchema ecosystem_schema() {
  TableSchema s;
  s.min_rows = 1;
  s.add("name", ColumnType::Text).describe("Ecosystem name (plants refer to it)");
  auto preference = [&](const std::string& name, Unit unit, double lo, double hi, const std::string& what) {
    s.add(name, ColumnType::Range)
        .range(lo, hi)
        .unit_of(unit)
        .optional()
        .describe("Preferred " + what + " [min, max]: membership 1 inside; left out: no preference");
    s.add(name + "_sharpness", ColumnType::Number)
        .range(1e-9, 1e9)
        .unit_of(Unit::Unitless)
        .optional()
        .describe("The " + name + " membership falls to 0 over (max - min) / sharpness outside the range; default 1");
  };
  preference("elevation", Unit::Metre, -1e6, 1e6, "height");
  preference("relative", Unit::Metre, -1e6, 1e6, "height above the local mean");
  preference("slope", Unit::Degree, -90.0, 90.0, "slope angle (0 flat, 90 vertical)");
  preference("skew", Unit::MetrePerMetre, -1e6, 1e6,
             "slope direction dz/dy (rise over run toward north, > 0 on south-facing slopes)");
  return s;
}

TableSchema ecosystem_plant_schema() {
  TableSchema s;
  s.add("ecosystem", ColumnType::Text).describe("The ecosystem (a name in `ecosystems`) the plant grows in");
  s.add("class", ColumnType::Integer).range(0, 1e6).unit_of(Unit::Id).describe("Class id of the plant's points");
  s.add("density", ColumnType::Number)
      .range(0.0, 100.0)
      .unit_of(Unit::PerSquareMetre)
      .describe("Plants per m^2 where the ecosystem holds, 0..100");
  s.add("scale", ColumnType::Range)
      .range(1e-9, 1e4)
      .unit_of(Unit::Factor)
      .describe("Scale factors [min, max], uniform between them");
  return s;
}

TableValue default_ecosystems() {
  return table_from_json_text(R"([
      {"name": "highland", "elevation": [70, 260], "elevation_sharpness": 2, "relative": [-1, 5],
       "relative_sharpness": 1, "slope": [0, 54.5], "slope_sharpness": 2},
      {"name": "marshland", "elevation": [-10, 50], "elevation_sharpness": 2, "relative": [-5, 0],
       "relative_sharpness": 1, "slope": [-21.8, 31], "slope_sharpness": 2},
      {"name": "plains", "elevation": [-50, 350], "elevation_sharpness": 2, "relative": [0.7, 3],
       "relative_sharpness": 1, "slope": [-21.8, 58], "slope_sharpness": 2},
      {"name": "slope", "elevation": [-50, 350], "elevation_sharpness": 2, "relative": [0, 10],
       "relative_sharpness": 1, "slope": [54.5, 67.4], "slope_sharpness": 2},
      {"name": "scarp", "elevation": [-50, 350], "elevation_sharpness": 2, "relative": [-10, 10],
       "relative_sharpness": 1, "slope": [70.3, 83.2], "slope_sharpness": 8}])",
                              ecosystem_schema());
}

TableValue default_ecosystem_plants() {
  return table_from_json_text(R"([
      {"ecosystem": "highland", "class": 0, "density": 0.008, "scale": [0.8, 2.0]},
      {"ecosystem": "highland", "class": 4, "density": 0.001, "scale": [0.8, 1.3]},
      {"ecosystem": "marshland", "class": 1, "density": 0.008, "scale": [1.2, 2.0]},
      {"ecosystem": "marshland", "class": 5, "density": 0.005, "scale": [1.5, 2.5]},
      {"ecosystem": "plains", "class": 2, "density": 0.008, "scale": [0.6, 1.1]},
      {"ecosystem": "plains", "class": 6, "density": 0.004, "scale": [0.3, 0.8]},
      {"ecosystem": "slope", "class": 4, "density": 0.001, "scale": [0.6, 1.8]},
      {"ecosystem": "scarp", "class": 4, "density": 0.001, "scale": [0.6, 1.8]},
      {"ecosystem": "scarp", "class": 7, "density": 0.001, "scale": [0.9, 1.0]}])",
                              ecosystem_plant_schema());
}

std::vector<Ecosystem> ecosystems_from_tables(const TableValue& ecosystems, const TableValue& plants) {
  std::vector<Ecosystem> out;
  for (std::size_t r = 0; r < ecosystems.rows.size(); ++r) {
    const auto& row = ecosystems.rows[r];
    Ecosystem e;
    e.name = std::get<std::string>(row[0]);
    RuleRange* ranges[] = {&e.elevation, &e.relative, &e.slope, &e.skew};
    for (std::size_t k = 0; k < 4; ++k) {
      const TableCell& range = row[1 + 2 * k];
      const TableCell& sharpness = row[2 + 2 * k];
      if (const auto* v = std::get_if<glm::dvec2>(&range)) {
        const auto* sh = std::get_if<double>(&sharpness);
        *ranges[k] = {true, v->x, v->y, sh ? *sh : 1.0};
      } else if (!std::holds_alternative<std::monostate>(sharpness)) {
        const auto& column = ecosystems.columns[2 + 2 * k];
        throw std::invalid_argument("ecosystems[" + std::to_string(r) + "]." + column + ": given without the range " +
                                    ecosystems.columns[1 + 2 * k]);
      }
    }
    out.push_back(std::move(e));
  }
  for (std::size_t r = 0; r < plants.rows.size(); ++r) {
    const auto& row = plants.rows[r];
    const auto& name = std::get<std::string>(row[0]);
    // A name given to two ecosystems: the plant grows in the first.
    auto it = std::find_if(out.begin(), out.end(), [&](const Ecosystem& e) { return e.name == name; });
    if (it == out.end())
      throw std::invalid_argument("plants[" + std::to_string(r) + "].ecosystem: '" + name +
                                  "' is not an ecosystem of the ecosystems table");
    const auto scale = std::get<glm::dvec2>(row[3]);
    it->plants.push_back(
        {static_cast<std::int32_t>(std::get<std::int64_t>(row[1])), std::get<double>(row[2]), scale.x, scale.y});
  }
  return out;
}

double RuleRange::membership(double v) const {
  if (!used) return 1.0;
  if (!std::isfinite(v)) return 0.0;
  if (v >= min && v <= max) return 1.0;
  const double margin = sharpness > 0.0 ? (max - min) / sharpness : INFINITY;
  const double d = v < min ? min - v : v - max;
  if (!(margin > 0.0)) return 0.0;
  return 1.0 - smoothstep01(d / margin);
}

double Ecosystem::membership(double e, double r, double s, double k) const {
  return elevation.membership(e) * relative.membership(r) * slope.membership(s) * skew.membership(k);
}

double TerrainVariables::elevation(double x, double y) const { return height->sample_world(x, y); }

double TerrainVariables::relative_at(double x, double y) const { return relative ? relative->sample_world(x, y) : 0.0; }

double TerrainVariables::slope_at(double x, double y) const {
  if (slope) return slope->sample_world(x, y);
  const auto sp = height->domain.spacing;
  const double gx = (height->sample_world(x + sp.x, y) - height->sample_world(x - sp.x, y)) / (2.0 * sp.x);
  const double gy = (height->sample_world(x, y + sp.y) - height->sample_world(x, y - sp.y)) / (2.0 * sp.y);
  return std::atan(std::hypot(gx, gy)) * (180.0 / kPi);
}

double TerrainVariables::skew_at(double x, double y) const {
  const auto sp = height->domain.spacing;
  return (height->sample_world(x, y + sp.y) - height->sample_world(x, y - sp.y)) / (2.0 * sp.y);
}

namespace {

// World cells [i0, i1] x [j0, j1] of side `cell` overlapping [lo, hi].
struct CellRange {
  std::int64_t i0, i1, j0, j1;
};
CellRange cells_over(glm::dvec2 lo, glm::dvec2 hi, double cell) {
  return {static_cast<std::int64_t>(std::floor(lo.x / cell)), static_cast<std::int64_t>(std::floor(hi.x / cell)),
          static_cast<std::int64_t>(std::floor(lo.y / cell)), static_cast<std::int64_t>(std::floor(hi.y / cell))};
}

void check_cells(const CellRange& c, double expected_per_cell) {
  const double n = static_cast<double>(c.i1 - c.i0 + 1) * static_cast<double>(c.j1 - c.j0 + 1);
  if (!(n <= 2e7) || !(n * expected_per_cell <= 5e7))
    throw std::runtime_error("the request covers too many cells or plants; raise cell_size or lower the densities");
}

// Rows of cells in parallel, each row's points in order, then concatenated in row order.
template <class Fn>
Points per_cell_rows(const CellRange& c, const ExecContext* ctx, Fn&& fn) {
  const int rows = static_cast<int>(c.j1 - c.j0 + 1);
  std::vector<Points> parts(static_cast<std::size_t>(rows));
  for_each_row(ctx, rows, [&](int r) {
    WorkPoll poll(ctx);  // a row may hold millions of cells (a thin, wide request)
    for (std::int64_t i = c.i0; i <= c.i1; ++i) {
      fn(i, c.j0 + r, parts[static_cast<std::size_t>(r)]);
      poll();
    }
  });
  Points out;
  for (auto& part : parts) {
    for (std::size_t k = 0; k < part.size(); ++k) {
      out.position.push_back(part.position[k]);
      out.rotation.push_back(part.rotation[k]);
      out.scale.push_back(part.scale[k]);
      out.class_id.push_back(part.class_id[k]);
    }
    for (auto& [name, values] : part.attributes) {
      auto& dst = out.attributes[name];
      dst.insert(dst.end(), values.begin(), values.end());
    }
  }
  // Attributes absent from some rows (rows without points) are sized by the rows that had them: fix up.
  for (auto& [name, values] : out.attributes)
    if (values.size() != out.size()) throw std::logic_error("scatter: inconsistent attribute " + name);
  return out;
}

bool inside(double x, double y, glm::dvec2 lo, glm::dvec2 hi) {
  return x >= lo.x && x <= hi.x && y >= lo.y && y <= hi.y;
}

}  // namespace

Points scatter_ecosystems(glm::dvec2 lo, glm::dvec2 hi, const TerrainVariables& vars, const EcosystemParams& p,
                          const ExecContext* ctx) {
  if (!vars.height) throw std::invalid_argument("ScatterRules: no height");
  if (!(p.cell_size > 0.0)) throw std::invalid_argument("ScatterRules: cell_size must be > 0");
  const CellRange cells = cells_over(lo, hi, p.cell_size);
  double per_cell = 0.0;
  for (const auto& e : p.ecosystems)
    for (const auto& pl : e.plants) per_cell += pl.density * p.cell_size * p.cell_size;
  check_cells(cells, per_cell);
  const std::size_t E = p.ecosystems.size();
  Points out = per_cell_rows(cells, ctx, [&](std::int64_t ci, std::int64_t cj, Points& dst) {
    WorkPoll poll(ctx);  // a large cell holds millions of candidates
    dst.attribute("ecosystem");
    std::vector<double> m(E);
    for (std::size_t e = 0; e < E; ++e)
      for (std::size_t pl = 0; pl < p.ecosystems[e].plants.size(); ++pl) {
        const RulePlant& plant = p.ecosystems[e].plants[pl];
        scatter::Draws draw{scatter::hash(p.seed, scatter::bits(ci), scatter::bits(cj), e, pl)};
        const double expected = plant.density * p.cell_size * p.cell_size;
        const auto n = static_cast<std::int64_t>(std::floor(expected + draw.next()));
        for (std::int64_t t = 0; t < n; ++t) {
          poll();
          const double x = (static_cast<double>(ci) + draw.next()) * p.cell_size;
          const double y = (static_cast<double>(cj) + draw.next()) * p.cell_size;
          const double u = draw.next(), angle = 2.0 * kPi * draw.next(), s = draw.next();
          if (!inside(x, y, lo, hi)) continue;
          const float fx = static_cast<float>(x), fy = static_cast<float>(y);
          const double elev = vars.elevation(fx, fy), rel = vars.relative_at(fx, fy), slope = vars.slope_at(fx, fy),
                       skew = vars.skew_at(fx, fy);
          double total = 0.0;
          for (std::size_t k = 0; k < E; ++k) total += m[k] = p.ecosystems[k].membership(elev, rel, slope, skew);
          // Roulette over the memberships; "none" takes what is missing below 1.
          double pick = u * std::max(1.0, total);
          std::size_t chosen = E;
          for (std::size_t k = 0; k < E; ++k) {
            if (pick < m[k]) {
              chosen = k;
              break;
            }
            pick -= m[k];
          }
          if (chosen != e) continue;
          const float z = static_cast<float>(elev);
          const std::size_t idx = dst.add({fx, fy, std::isfinite(z) ? z : 0.0f}, plant.class_id);
          dst.rotation[idx] = yaw(angle);
          dst.scale[idx] = glm::vec3(static_cast<float>(plant.scale_min + s * (plant.scale_max - plant.scale_min)));
          dst.attribute("ecosystem")[idx] = static_cast<float>(e);
        }
      }
  });
  out.attribute("ecosystem");
  return out;
}

TableSchema biome_density_schema() {
  TableSchema s;
  s.min_rows = 1;
  s.add("biome", ColumnType::Integer)
      .range(-1e6, 1e6)
      .unit_of(Unit::Id)
      .describe("Biome id (the input's integer values)");
  s.add("density", ColumnType::Number)
      .range(0.0, 1.0)
      .unit_of(Unit::Unitless)
      .describe("Probability of a plant per cell, 0..1");
  return s;
}

TableSchema biome_species_schema() {
  TableSchema s;
  s.add("biome", ColumnType::Integer)
      .range(-1e6, 1e6)
      .unit_of(Unit::Id)
      .describe("The biome (an id in `biomes`) the species grows in");
  s.add("class", ColumnType::Integer).range(0, 1e6).unit_of(Unit::Id).describe("Class id of the species' points");
  s.add("weight", ColumnType::Number)
      .range(0.0, 1e12)
      .unit_of(Unit::Unitless)
      .describe("Relative weight among the biome's species, >= 0");
  return s;
}

std::vector<BiomeEntry> biome_entries_from_tables(const TableValue& biomes, const TableValue& species) {
  std::vector<BiomeEntry> out;
  for (const auto& row : biomes.rows)
    out.push_back({static_cast<int>(std::get<std::int64_t>(row[0])), std::get<double>(row[1]), {}});
  for (std::size_t r = 0; r < species.rows.size(); ++r) {
    const auto& row = species.rows[r];
    const auto biome = static_cast<int>(std::get<std::int64_t>(row[0]));
    bool found = false;
    for (auto& b : out) {
      if (b.biome != biome) continue;
      b.species.emplace_back(static_cast<std::int32_t>(std::get<std::int64_t>(row[1])), std::get<double>(row[2]));
      found = true;
    }
    if (!found)
      throw std::invalid_argument("species[" + std::to_string(r) + "].biome: " + std::to_string(biome) +
                                  " is not a biome of the biomes table");
  }
  return out;
}

Points scatter_biomes(glm::dvec2 lo, glm::dvec2 hi, const Heightfield& biome, const Heightfield* height,
                      const BiomeScatterParams& p, const ExecContext* ctx) {
  if (!(p.cell_size > 0.0)) throw std::invalid_argument("BiomeScatter: cell_size must be > 0");
  const CellRange cells = cells_over(lo, hi, p.cell_size);
  check_cells(cells, 1.0);
  Points out = per_cell_rows(cells, ctx, [&](std::int64_t ci, std::int64_t cj, Points& dst) {
    scatter::Draws draw{scatter::hash(p.seed, 0xB10ull, scatter::bits(ci), scatter::bits(cj))};
    const double u = draw.next(), w = draw.next();
    const double x = (static_cast<double>(ci) + draw.next()) * p.cell_size;
    const double y = (static_cast<double>(cj) + draw.next()) * p.cell_size;
    const double angle = 2.0 * kPi * draw.next(), s = draw.next();
    if (!inside(x, y, lo, hi)) return;
    // The biome of the cell: nearest sample to its centre.
    const auto st = biome.domain.to_sample(
        {(static_cast<double>(ci) + 0.5) * p.cell_size, (static_cast<double>(cj) + 0.5) * p.cell_size});
    const int bi = std::clamp(static_cast<int>(std::lround(st.x)), 0, biome.width() - 1);
    const int bj = std::clamp(static_cast<int>(std::lround(st.y)), 0, biome.height() - 1);
    const float id = biome.at(bi, bj);
    if (!std::isfinite(id)) return;
    const BiomeEntry* entry = nullptr;
    for (const auto& b : p.table)
      if (b.biome == static_cast<int>(std::lround(id))) entry = &b;
    if (!entry || entry->species.empty()) return;
    if (!(u < std::min(1.0, entry->density * p.factor))) return;
    double total = 0.0;
    for (const auto& sp : entry->species) total += sp.second;
    if (!(total > 0.0)) return;
    double pick = w * total;
    std::int32_t cls = entry->species.back().first;
    for (const auto& sp : entry->species) {
      if (pick < sp.second) {
        cls = sp.first;
        break;
      }
      pick -= sp.second;
    }
    const float fx = static_cast<float>(x), fy = static_cast<float>(y);
    float z = height ? height->sample_world(fx, fy) : 0.0f;
    if (!std::isfinite(z)) z = 0.0f;
    const std::size_t idx = dst.add({fx, fy, z}, cls);
    dst.rotation[idx] = yaw(angle);
    dst.scale[idx] = glm::vec3(static_cast<float>(p.scale_min + s * (p.scale_max - p.scale_min)));
    dst.attribute("biome")[idx] = static_cast<float>(entry->biome);
  });
  out.attribute("biome");
  return out;
}

}  // namespace orogen
