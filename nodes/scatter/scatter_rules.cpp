#include "nodes/scatter/scatter_rules.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>

#include "graph/exec_context.h"
#include "nodes/common/text.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/scatter/scatter_hash.h"

namespace orogen {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Lines split at '\n' and ';', comments ('#' to the end of the line) removed, blank lines dropped.
std::vector<std::string> table_lines(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  bool comment = false;
  for (char c : text) {
    if (c == '\n' || c == ';') {
      if (!trim(cur).empty()) out.push_back(trim(cur));
      cur.clear();
      comment = false;
    } else if (c == '#') {
      comment = true;
    } else if (!comment) {
      cur += c;
    }
  }
  if (!trim(cur).empty()) out.push_back(trim(cur));
  return out;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

std::vector<double> numbers(std::istringstream& in, int count, const std::string& where) {
  std::vector<double> v;
  for (int i = 0; i < count; ++i) {
    double x;
    if (!(in >> x) || !std::isfinite(x)) throw std::invalid_argument(where + ": expected " + std::to_string(count) + " numbers");
    v.push_back(x);
  }
  std::string extra;
  if (in >> extra) throw std::invalid_argument(where + ": unexpected '" + extra + "'");
  return v;
}

double smoothstep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

glm::quat yaw(double angle) { return glm::angleAxis(static_cast<float>(angle), glm::vec3(0.0f, 0.0f, 1.0f)); }

}  // namespace

const char* const kDefaultEcosystemTable =
    "highland  | elevation 70 260 2  | relative -1 5 1   | slope 0 1.4 2    | plant 0 0.008 0.8 2.0 | plant 4 0.001 0.8 1.3\n"
    "marshland | elevation -10 50 2  | relative -5 0 1   | slope -0.4 0.6 2 | plant 1 0.008 1.2 2.0 | plant 5 0.005 1.5 2.5\n"
    "plains    | elevation -50 350 2 | relative 0.7 3 1  | slope -0.4 1.6 2 | plant 2 0.008 0.6 1.1 | plant 6 0.004 0.3 0.8\n"
    "slope     | elevation -50 350 2 | relative 0 10 1   | slope 1.4 2.4 2  | plant 4 0.001 0.6 1.8\n"
    "scarp     | elevation -50 350 2 | relative -10 10 1 | slope 2.8 8.4 8  | plant 4 0.001 0.6 1.8 | plant 7 0.001 0.9 1.0\n";

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

std::vector<Ecosystem> parse_ecosystem_table(const std::string& text) {
  std::vector<Ecosystem> out;
  int line_no = 0;
  for (const auto& line : table_lines(text)) {
    ++line_no;
    const auto fields = split(line, '|');
    Ecosystem e;
    e.name = fields[0];
    const std::string where = "ecosystem " + std::to_string(line_no) + " ('" + e.name + "')";
    if (e.name.empty()) throw std::invalid_argument(where + ": no name");
    for (std::size_t f = 1; f < fields.size(); ++f) {
      std::istringstream in(fields[f]);
      std::string key;
      in >> key;
      const std::string w = where + ", '" + key + "'";
      if (key == "elevation" || key == "relative" || key == "slope" || key == "skew") {
        const auto v = numbers(in, 3, w);
        if (v[1] < v[0]) throw std::invalid_argument(w + ": max below min");
        if (v[2] <= 0.0) throw std::invalid_argument(w + ": sharpness must be > 0");
        RuleRange& r = key == "elevation" ? e.elevation : key == "relative" ? e.relative : key == "slope" ? e.slope : e.skew;
        r = {true, v[0], v[1], v[2]};
      } else if (key == "plant") {
        const auto v = numbers(in, 4, w);
        if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e6) throw std::invalid_argument(w + ": class must be an integer in [0, 1e6]");
        if (v[1] < 0.0 || v[1] > 100.0) throw std::invalid_argument(w + ": density must be in [0, 100] per m^2");
        if (v[2] <= 0.0 || v[3] < v[2] || v[3] > 1e4) throw std::invalid_argument(w + ": scales must satisfy 0 < min <= max <= 1e4");
        e.plants.push_back({static_cast<std::int32_t>(v[0]), v[1], v[2], v[3]});
      } else {
        throw std::invalid_argument(w + ": unknown field (elevation, relative, slope, skew or plant)");
      }
    }
    out.push_back(std::move(e));
  }
  if (out.empty()) throw std::invalid_argument("the ecosystem table is empty");
  return out;
}

double TerrainVariables::elevation(double x, double y) const { return height->sample_world(x, y); }

double TerrainVariables::relative_at(double x, double y) const { return relative ? relative->sample_world(x, y) : 0.0; }

double TerrainVariables::slope_at(double x, double y) const {
  if (slope) return slope->sample_world(x, y);
  const auto sp = height->domain.spacing;
  const double gx = (height->sample_world(x + sp.x, y) - height->sample_world(x - sp.x, y)) / (2.0 * sp.x);
  const double gy = (height->sample_world(x, y + sp.y) - height->sample_world(x, y - sp.y)) / (2.0 * sp.y);
  return std::hypot(gx, gy);
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
    for (std::int64_t i = c.i0; i <= c.i1; ++i) fn(i, c.j0 + r, parts[static_cast<std::size_t>(r)]);
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

bool inside(double x, double y, glm::dvec2 lo, glm::dvec2 hi) { return x >= lo.x && x <= hi.x && y >= lo.y && y <= hi.y; }

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
    dst.attribute("ecosystem");
    std::vector<double> m(E);
    for (std::size_t e = 0; e < E; ++e)
      for (std::size_t pl = 0; pl < p.ecosystems[e].plants.size(); ++pl) {
        const RulePlant& plant = p.ecosystems[e].plants[pl];
        scatter::Draws draw{scatter::hash(p.seed, scatter::bits(ci), scatter::bits(cj), e, pl)};
        const double expected = plant.density * p.cell_size * p.cell_size;
        const auto n = static_cast<std::int64_t>(std::floor(expected + draw.next()));
        for (std::int64_t t = 0; t < n; ++t) {
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

std::vector<BiomeEntry> parse_biome_table(const std::string& text) {
  std::vector<BiomeEntry> out;
  int line_no = 0;
  for (const auto& line : table_lines(text)) {
    ++line_no;
    const auto fields = split(line, '|');
    const std::string where = "biome line " + std::to_string(line_no);
    BiomeEntry b;
    {
      std::istringstream in(fields[0]);
      const auto v = numbers(in, 2, where);
      if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 1e6) throw std::invalid_argument(where + ": biome id must be an integer");
      if (v[1] < 0.0 || v[1] > 1.0) throw std::invalid_argument(where + ": density must be in [0, 1]");
      b.biome = static_cast<int>(v[0]);
      b.density = v[1];
    }
    for (std::size_t f = 1; f < fields.size(); ++f) {
      std::istringstream in(fields[f]);
      const auto v = numbers(in, 2, where);
      if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 1e6) throw std::invalid_argument(where + ": class must be an integer in [0, 1e6]");
      if (v[1] < 0.0) throw std::invalid_argument(where + ": weights must be >= 0");
      b.species.emplace_back(static_cast<std::int32_t>(v[0]), v[1]);
    }
    out.push_back(std::move(b));
  }
  if (out.empty()) throw std::invalid_argument("the biome table is empty");
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
    const auto st = biome.domain.to_sample({(static_cast<double>(ci) + 0.5) * p.cell_size, (static_cast<double>(cj) + 0.5) * p.cell_size});
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
