#include "nodes/climate/biomes.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include <nlohmann/json.hpp>

#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/hex_color.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/report_builder.h"
#include "nodes/common/text.h"

namespace orogen::climate {

int BiomeTable::classify(double t, double m) const {
  for (const auto& r : rows)
    if (t >= r.t_min && t < r.t_max && m >= r.m_min && m < r.m_max) return r.id;
  return -1;
}

std::string builtin_biome_table(const std::string& name) {
  if (name == "whittaker")
    return "tundra, -inf, -5, -inf, inf, #b7c5c8\n"
           "boreal_forest, -5, 5, 250, inf, #2f5d3a\n"
           "temperate_grassland_desert, -5, 20, -inf, 500, #d8c48a\n"
           "woodland_shrubland, 5, 20, 500, 1000, #a2a452\n"
           "temperate_seasonal_forest, 5, 20, 1000, 2000, #5f9b3e\n"
           "temperate_rain_forest, 5, 20, 2000, inf, #2c7a5a\n"
           "subtropical_desert, 20, inf, -inf, 600, #e6c37a\n"
           "tropical_seasonal_forest_savanna, 20, inf, 600, 2500, #9dbb3c\n"
           "tropical_rain_forest, 20, inf, 2500, inf, #1e6b2a\n";
  if (name == "island")
    return "scorched, -inf, 0, -inf, 0.16667, #555555\n"
           "bare, -inf, 0, 0.16667, 0.33333, #888888\n"
           "tundra, -inf, 0, 0.33333, 0.5, #bbbbaa\n"
           "snow, -inf, 0, 0.5, inf, #ffffff\n"
           "temperate_desert, 0, 8, -inf, 0.33333, #c9d29b\n"
           "shrubland, 0, 8, 0.33333, 0.66667, #889977\n"
           "taiga, 0, 8, 0.66667, inf, #99aa77\n"
           "temperate_desert, 8, 16, -inf, 0.16667, #c9d29b\n"
           "grassland, 8, 16, 0.16667, 0.5, #88aa55\n"
           "temperate_deciduous_forest, 8, 16, 0.5, 0.83333, #679459\n"
           "temperate_rain_forest, 8, 16, 0.83333, inf, #448855\n"
           "subtropical_desert, 16, inf, -inf, 0.16667, #d2b98b\n"
           "grassland, 16, inf, 0.16667, 0.33333, #88aa55\n"
           "tropical_seasonal_forest, 16, inf, 0.33333, 0.66667, #559944\n"
           "tropical_rain_forest, 16, inf, 0.66667, inf, #337755\n";
  return "";
}

BiomeTable parse_biome_table(const std::string& text) {
  BiomeTable t;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    std::vector<std::string> f;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) f.push_back(trim(cell));
    const std::string where = "biome table line " + std::to_string(number) + ": ";
    if (f.size() != 6) throw NodeError(where + "expected 'name, t_min, t_max, m_min, m_max, #rrggbb', got " + std::to_string(f.size()) + " fields");
    BiomeRow r;
    r.name = f[0];
    if (r.name.empty()) throw NodeError(where + "empty name");
    double v[4];
    for (int k = 0; k < 4; ++k) {
      char* end = nullptr;
      v[k] = std::strtod(f[static_cast<std::size_t>(k + 1)].c_str(), &end);
      if (f[static_cast<std::size_t>(k + 1)].empty() || *end != '\0' || std::isnan(v[k]))
        throw NodeError(where + "'" + f[static_cast<std::size_t>(k + 1)] + "' is not a number");
    }
    r.t_min = v[0];
    r.t_max = v[1];
    r.m_min = v[2];
    r.m_max = v[3];
    const std::string& c = f[5];
    const auto hex = parse_hex_color(c);
    if (!hex) throw NodeError(where + "color '" + c + "' is not #rrggbb");
    const glm::vec4 color = hex_to_linear(*hex);
    r.id = -1;
    for (std::size_t k = 0; k < t.names.size(); ++k)
      if (t.names[k] == r.name) r.id = static_cast<int>(k);
    if (r.id < 0) {
      r.id = static_cast<int>(t.names.size());
      t.names.push_back(r.name);
      t.colors.push_back(color);
    }
    t.rows.push_back(r);
  }
  if (t.rows.empty()) throw NodeError("biome table has no rows");
  return t;
}

BiomeResult classify_biomes(const Heightfield& temperature, const Heightfield& moisture, const BiomeTable& table,
                            double moisture_scale, const ExecContext* ctx) {
  require_same_grid(moisture.domain, temperature.domain, "moisture");
  BiomeResult out{std::make_shared<Heightfield>(temperature.domain), std::make_shared<Image>(temperature.domain, 4)};
  out.color->channel_names = {"R", "G", "B", "A"};
  const glm::vec4 none(0.2f, 0.2f, 0.2f, 1.0f);
  for_each_row(ctx, temperature.height(), [&](int j) {
    for (int i = 0; i < temperature.width(); ++i) {
      const int id = table.classify(temperature.at(i, j), moisture.at(i, j) * moisture_scale);
      out.ids->at(i, j) = static_cast<float>(id);
      const glm::vec4 c = id >= 0 ? table.colors[static_cast<std::size_t>(id)] : none;
      float* px = out.color->pixel(i, j);
      for (int k = 0; k < 4; ++k) px[k] = c[k];
    }
  });
  return out;
}

OROGEN_NODE(Biomes) {
  b.reach_pointwise();
  b.category("climate").description(
      "Biome per cell from temperature and moisture through an editable table of rectangles. Built in: "
      "'whittaker', a rectangular reading of R. H. Whittaker (1975), Communities and Ecosystems (as redrawn "
      "by R. E. Ricklefs (2008), The Economy of Nature), moisture = annual precipitation in mm: tundra, "
      "boreal forest, temperate grassland/desert, woodland/shrubland, temperate seasonal and rain forest, "
      "subtropical desert, tropical seasonal forest/savanna, tropical rain forest; 'island', the elevation x "
      "moisture table of A. Patel (2010), Polygonal Map Generation for Games, as S. Weiss (2015), Procedural "
      "Terrain, uses it, with moisture in 0..1 and temperature bands < 0, 0..8, 8..16, >= 16 C for the "
      "elevation zones. 'custom': the custom_table text, one row per line 'name, t_min, t_max, m_min, "
      "m_max, #rrggbb' (min inclusive, max exclusive, inf allowed; the first matching row wins; ids number "
      "the distinct names in order; -1 where no row matches). The report lists ids, names and colors.");
  b.input("in", PortType::Heightfield).description("Temperature, deg C (e.g. Temperature.mean)");
  b.input("moisture", PortType::Heightfield).description("Moisture in the table's unit (whittaker: mm per year; island: 0..1)");
  b.output("out", PortType::Heightfield).description("Biome id 0, 1, ... (-1: no row matches)").kind(OutputKind::Scalar);
  b.output("color", PortType::Image).description("Biome colors, linear RGBA");
  b.output("report", PortType::Report).description("The table: id, name, color per biome");
  b.param_enum("table", {"whittaker", "island", "custom"}, "whittaker").description("Which table classifies");
  b.param_string("custom_table", builtin_biome_table("whittaker")).description("Rows 'name, t_min, t_max, m_min, m_max, #rrggbb' used when table = custom");
  b.param_float("moisture_scale", 1.0).range(0.0, 1e6).description("Multiplier of the moisture input before the lookup (unit conversion), >= 0");
  b.execute([](ExecContext& ctx) {
    const std::string which = ctx.param<std::string>("table");
    const BiomeTable table = parse_biome_table(which == "custom" ? ctx.param<std::string>("custom_table") : builtin_biome_table(which));
    const auto in = ctx.require<Heightfield>("in");
    const auto moisture = require_secondary_input<Heightfield>(ctx, "moisture", in->domain);
    auto r = classify_biomes(*in, *moisture, table, ctx.param<double>("moisture_scale"), &ctx);
    ReportJson j = ReportJson::array();
    for (std::size_t k = 0; k < table.names.size(); ++k)
      j.push_back({{"id", k}, {"name", table.names[k]}, {"color", {table.colors[k].r, table.colors[k].g, table.colors[k].b}}});
    const auto report = make_report(ReportJson{{"biomes", j}});
    ctx.set_output("out", r.ids);
    ctx.set_output("color", r.color);
    ctx.set_output("report", report);
  });
}

}  // namespace orogen::climate
