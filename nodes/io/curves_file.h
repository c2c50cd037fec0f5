#pragma once
// Curves (river networks, feature curves) to GeoJSON-like JSON and to Wavefront OBJ lines.
//
// JSON: a GeoJSON FeatureCollection; each curve is a Feature with a LineString of [x, y, z] (world metres, z up)
// and properties: "index" (its position), "parent" (index of the curve it flows into, -1 for none), "width"
// (per vertex, metres) and every named attribute as a per-vertex array. (GeoJSON proper would need a
// geographic CRS; these coordinates are the terrain's metres.)
// OBJ: "v x y z" per vertex and one "l" element per curve (1-based indices), each curve in its own group
// "g curve_<index>"; a comment line "# parent <index> <parent>" per curve and per-vertex attributes as
// "# attr <name> <values...>" comment lines, which OBJ readers ignore.
// Numbers are written in the shortest form that reads back as the same float. Not atomic by itself.
#include <filesystem>
#include <optional>

#include "graph/curves.h"
#include "nodes/io/file_error.h"

namespace orogen {

enum class CurvesFormat { Json, Obj };

std::optional<CurvesFormat> curves_format_from_path(const std::filesystem::path& path);

// Throws FileError on failure.
void write_curves_file(const Curves& curves, const std::filesystem::path& path, CurvesFormat format,
                       const WriteProgress& progress = {});

}  // namespace orogen
