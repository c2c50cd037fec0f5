#pragma once
// Biome classification by temperature and moisture through an editable table of rectangles.
//
// A table parameter, one row per rectangle: name, temperature [min, max] (deg C), moisture [min, max] (the
// table's unit), color #rrggbb; min inclusive, max exclusive; null bounds for open ends. The first row containing
// (T, M) wins. Biome ids number the distinct names in order of first appearance (a name may own several
// rows); cells no row contains get id -1.
#include <memory>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/table_value.h"

namespace orogen::climate {

struct BiomeRow {
  std::string name;
  double t_min, t_max, m_min, m_max;
  int id = 0;
};

struct BiomeTable {
  std::vector<BiomeRow> rows;
  std::vector<std::string> names;  // by id
  std::vector<glm::vec4> colors;   // by id, linear RGBA

  int classify(double t, double m) const;
};

// The rectangles' table: its columns, and built-in tables: "whittaker" (annual precipitation in mm; a rectangular
// reading of R. H. Whittaker (1975), Communities and Ecosystems, as redrawn by R. E. Ricklefs (2008), The Economy of
// Nature) and "island" (moisture 0..1; the elevation-zone x moisture-zone table of A. Patel (2010), Polygonal Map
// Generation for Games, used by S. Weiss (2015), Procedural Terrain, with temperature bands for the zones).
TableSchema biome_rectangle_schema();
TableValue builtin_biome_rectangles(const std::string& name);  // empty rows for an unknown name
// The classification of the table's rows (ids number the distinct names). Throws NodeError for no rows.
BiomeTable biome_table_from_rows(const TableValue& rows);

struct BiomeResult {
  std::shared_ptr<Heightfield> ids;
  std::shared_ptr<Image> color;
};
BiomeResult classify_biomes(const Heightfield& temperature, const Heightfield& moisture, const BiomeTable& table,
                            double moisture_scale = 1.0, const ExecContext* ctx = nullptr);

}  // namespace orogen::climate
