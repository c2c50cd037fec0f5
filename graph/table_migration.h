#pragma once
// Graph format version 5 replaced six string mini-languages by table parameters (graph/table_value.h).
// The old parsers live on here as the migration that turns the strings of version-4 files into tables.
#include <nlohmann/json_fwd.hpp>

namespace orogen {

// Rewrites, in every node of a version-4 file:
//   Biomes.custom_table     "name, t_min, t_max, m_min, m_max, #rrggbb" lines -> rows (inf -> null)
//   BiomeScatter.table      "ID DENSITY | CLASS WEIGHT | ..." lines -> `biomes` and `species`
//   ScatterRules.table      "NAME | elevation MIN MAX SHARPNESS | ... | plant CLASS DENSITY SMIN SMAX" lines
//                           -> `ecosystems` and `plants`, slopes from rise/run to degrees (atan); a node
//                           without a table gets the old default converted
//   SplatWeights.layers     "name: input < t ~ s, ..., weight = w" lines -> `layers` and `rules`
//   ColorByLayers.colors    "name #rrggbb" entries -> rows
//   Instance.names          "a, b, , d" -> rows {class, name} of the non-empty names
// Parameters that are not strings are left for the loader to report. A string the old parser refused
// throws std::runtime_error naming the node, the parameter and the line.
void convert_string_tables_v4(nlohmann::json& file);

}  // namespace orogen
