#pragma once
// The history of the graph file format: what each version changed and how older files are rewritten.
//
// Version 2 (port and spelling convention, docs/conventions.md): a node's primary input is `in` and its
// primary output `out`; everything a user types is spelled American. The renames are data, one entry per
// node type, so the migration and its tests read the same table.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace orogen {

struct Rename {
  std::string from, to;
};

struct EnumValueRename {
  std::string param;  // the parameter's name in version 2
  std::string from, to;
};

// What changed for one node type between two format versions (1 -> 2, 5 -> 6).
struct NodeRenamesV1 {
  std::string type;
  std::vector<Rename> inputs;
  std::vector<Rename> outputs;
  std::vector<Rename> params;
  std::vector<EnumValueRename> enum_values;
};

const std::vector<NodeRenamesV1>& format_v1_renames();

// Version 3: parameters whose default changed; files that relied on the old default get it written out,
// so they keep their meaning. ReadHeightfield.size: [1024, 1024] -> [0, 0] (the requested domain).
struct ChangedDefault {
  std::string type, param;
  std::string old_default;  // JSON text
};
const std::vector<ChangedDefault>& format_v2_changed_defaults();
void migrate_graph_v2_to_v3(nlohmann::json& file);

// Version 4: WriteScene takes a Scene (`in`) made by the new Instance node from the points and the class
// meshes it used to take itself (`in`: Points, `mesh_0`..`mesh_7`, `proxies`). Every WriteScene of an older
// file gets an Instance node (id "<writer id>_instance", made unique) inserted before it with those links,
// missing_mesh = proxy (proxies true, the old default) or skip (proxies false), and placed left of the
// writer in the editor.
void migrate_graph_v3_to_v4(nlohmann::json& file);

// Version 5: the six string mini-languages became table parameters (graph/table_value.h); the strings of
// older files are converted by convert_string_tables_v4 (graph/table_migration.h).
void migrate_graph_v4_to_v5(nlohmann::json& file);

// Version 6: one name per quantity (the glossary of docs/conventions.md). Ports and parameters renamed by
// format_v5_renames(); two parameters also change their unit, and the migration converts their values so the
// outputs stay the same (format_v5_converted_params): SunIllumination.month 1..12 becomes day_of_year (the
// 15th of that month; the node uses the month holding the day), Turtle3D.tropism_strength radians become
// degrees (a degree value that converts back to the same radians).
const std::vector<NodeRenamesV1>& format_v5_renames();
struct ConvertedParam {
  std::string type, param;  // the parameter's name in version 6
  std::string conversion;
};
const std::vector<ConvertedParam>& format_v5_converted_params();
void migrate_graph_v5_to_v6(nlohmann::json& file);

// Version 7: WriteMesh.up_axis gains `auto` (the new default): y-up for OBJ, as Blender, Maya and most DCC
// tools import it, z-up for PLY and STL (3D printing, point-cloud tools); glTF is y-up whatever the setting.
// An OBJ writer of an older file that relied on the old default (Z) gets it written out, so its file keeps its
// axes; PLY and STL writers keep theirs under `auto` and are left alone.
void migrate_graph_v6_to_v7(nlohmann::json& file);

// Rewrites a version-1 file in place: input port names in "inputs", output port names in every link that
// reads a renamed output, parameter names and enum values in "params". Parts of the file that are not
// well formed are left as they are, for the loader to report.
void migrate_graph_v1_to_v2(nlohmann::json& file);

}  // namespace orogen
