#include "nodes/climate/biomes.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "graph/registry.h"
#include "graph/report.h"
#include "graph/table_json.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/report_builder.h"

namespace orogen::climate {

int BiomeTable::classify(double t, double m) const {
  for (const auto& r : rows)
    if (t >= r.t_min && t < r.t_max && m >= r.m_min && m < r.m_max) return r.id;
  return -1;
}

TableSchema biome_rectangle_schema() {
  TableSchema s;
  s.min_rows = 1;
  s.add("name", ColumnType::Text).describe("Biome name; rows sharing a name are one biome");
  s.add("temperature", ColumnType::Range)
      .unit_of(Unit::DegreeCelsius)
      .allow_open_ends()
      .describe("Temperatures of the rectangle, [min, max): min inclusive, max exclusive");
  s.add("moisture", ColumnType::Range)
      .unit_of(Unit::InputUnits)
      .allow_open_ends()
      .describe("Moisture of the rectangle in the table's unit (whittaker: mm per year; island: 0..1), [min, max)");
  s.add("color", ColumnType::Color).describe("The biome's color, sRGB #rrggbb (its first row's counts)");
  return s;
}

TableValue builtin_biome_rectangles(const std::string& name) {
  if (name == "whittaker")
    return table_from_json_text(R"([
      {"name": "tundra", "temperature": [null, -5], "moisture": [null, null], "color": "#b7c5c8"},
      {"name": "boreal_forest", "temperature": [-5, 5], "moisture": [250, null], "color": "#2f5d3a"},
      {"name": "temperate_grassland_desert", "temperature": [-5, 20], "moisture": [null, 500], "color": "#d8c48a"},
      {"name": "woodland_shrubland", "temperature": [5, 20], "moisture": [500, 1000], "color": "#a2a452"},
      {"name": "temperate_seasonal_forest", "temperature": [5, 20], "moisture": [1000, 2000], "color": "#5f9b3e"},
      {"name": "temperate_rain_forest", "temperature": [5, 20], "moisture": [2000, null], "color": "#2c7a5a"},
      {"name": "subtropical_desert", "temperature": [20, null], "moisture": [null, 600], "color": "#e6c37a"},
      {"name": "tropical_seasonal_forest_savanna", "temperature": [20, null], "moisture": [600, 2500],
       "color": "#9dbb3c"},
      {"name": "tropical_rain_forest", "temperature": [20, null], "moisture": [2500, null], "color": "#1e6b2a"}])",
                                biome_rectangle_schema());
  if (name == "island")
    return table_from_json_text(R"([
      {"name": "scorched", "temperature": [null, 0], "moisture": [null, 0.16667], "color": "#555555"},
      {"name": "bare", "temperature": [null, 0], "moisture": [0.16667, 0.33333], "color": "#888888"},
      {"name": "tundra", "temperature": [null, 0], "moisture": [0.33333, 0.5], "color": "#bbbbaa"},
      {"name": "snow", "temperature": [null, 0], "moisture": [0.5, null], "color": "#ffffff"},
      {"name": "temperate_desert", "temperature": [0, 8], "moisture": [null, 0.33333], "color": "#c9d29b"},
      {"name": "shrubland", "temperature": [0, 8], "moisture": [0.33333, 0.66667], "color": "#889977"},
      {"name": "taiga", "temperature": [0, 8], "moisture": [0.66667, null], "color": "#99aa77"},
      {"name": "temperate_desert", "temperature": [8, 16], "moisture": [null, 0.16667], "color": "#c9d29b"},
      {"name": "grassland", "temperature": [8, 16], "moisture": [0.16667, 0.5], "color": "#88aa55"},
      {"name": "temperate_deciduous_forest", "temperature": [8, 16], "moisture": [0.5, 0.83333], "color": "#679459"},
      {"name": "temperate_rain_forest", "temperature": [8, 16], "moisture": [0.83333, null], "color": "#448855"},
      {"name": "subtropical_desert", "temperature": [16, null], "moisture": [null, 0.16667], "color": "#d2b98b"},
      {"name": "grassland", "temperature": [16, null], "moisture": [0.16667, 0.33333], "color": "#88aa55"},
      {"name": "tropical_seasonal_forest", "temperature": [16, null], "moisture": [0.33333, 0.66667],
       "color": "#559944"},
      {"name": "tropical_rain_forest", "temperature": [16, null], "moisture": [0.66667, null], "color": "#337755"}])",
                                biome_rectangle_schema());
  return empty_table(biome_rectangle_schema());
}

BiomeTable biome_table_from_rows(const TableValue& rows) {
  BiomeTable t;
  for (const auto& row : rows.rows) {
    BiomeRow r;
    r.name = std::get<std::string>(row[0]);
    const auto temperature = std::get<glm::dvec2>(row[1]), moisture = std::get<glm::dvec2>(row[2]);
    r.t_min = temperature.x;
    r.t_max = temperature.y;
    r.m_min = moisture.x;
    r.m_max = moisture.y;
    r.id = -1;
    for (std::size_t k = 0; k < t.names.size(); ++k)
      if (t.names[k] == r.name) r.id = static_cast<int>(k);
    if (r.id < 0) {
      r.id = static_cast<int>(t.names.size());
      t.names.push_back(r.name);
      t.colors.push_back(std::get<Srgb8>(row[3]).linear());
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
  out.color->color = true;
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
      "elevation zones. 'custom': the custom_table, one row per rectangle (name, temperature and moisture "
      "ranges, min inclusive, max exclusive, open ends allowed; color); the first matching row wins; ids number "
      "the distinct names in order; -1 where no row matches). The report lists ids, names and colors.");
  b.input("in", PortType::Heightfield).description("Temperature, deg C (e.g. Temperature.mean)");
  b.input("moisture", PortType::Heightfield)
      .description("Moisture in the table's unit (whittaker: mm per year; island: 0..1)");
  b.output("out", PortType::Heightfield)
      .description("Biome id 0, 1, ... (-1: no row matches)")
      .kind(OutputKind::Scalar);
  b.output("color", PortType::Image).description("Biome colors, linear RGBA");
  b.output("report", PortType::Report).description("The table: id, name, color per biome");
  b.param_enum("table", {"whittaker", "island", "custom"}, "whittaker").description("Which table classifies");
  b.param_table("custom_table", biome_rectangle_schema(), builtin_biome_rectangles("whittaker"))
      .description("The rectangles used when table = custom: name, temperature and moisture ranges, color");
  b.param_float("moisture_scale", 1.0)
      .unit(Unit::Factor)
      .range(0.0, 1e6)
      .description("Multiplier of the moisture input before the lookup (unit conversion), >= 0");
  b.execute([](ExecContext& ctx) {
    const std::string which = ctx.param<std::string>("table");
    const BiomeTable table = biome_table_from_rows(which == "custom" ? ctx.param<TableValue>("custom_table")
                                                                     : builtin_biome_rectangles(which));
    const auto in = ctx.require<Heightfield>("in");
    const auto moisture = require_secondary_input<Heightfield>(ctx, "moisture", in->domain);
    auto r = classify_biomes(*in, *moisture, table, ctx.param<double>("moisture_scale"), &ctx);
    ReportJson j = ReportJson::array();
    for (std::size_t k = 0; k < table.names.size(); ++k)
      j.push_back(
          {{"id", k}, {"name", table.names[k]}, {"color", {table.colors[k].r, table.colors[k].g, table.colors[k].b}}});
    const auto report = make_report(ReportJson{{"biomes", j}});
    ctx.set_output("out", r.ids);
    ctx.set_output("color", r.color);
    ctx.set_output("report", report);
  });
}

}  // namespace orogen::climate
