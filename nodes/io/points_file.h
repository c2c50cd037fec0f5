#pragma once
// Points (scatter results, river sources, ...) to CSV and ASCII PLY.
//
// Columns, in this order: x, y, z (world metres, z up), qw, qx, qy, qz (rotation quaternion), sx, sy, sz
// (per-axis scale), class (integer class id), then every named attribute sorted by name. Numbers are written
// in the shortest form that reads back as the same float.
#include <filesystem>
#include <optional>

#include "graph/points.h"
#include "nodes/io/file_error.h"

namespace orogen {

enum class PointsFormat { Csv, Ply };

std::optional<PointsFormat> points_format_from_path(const std::filesystem::path& path);

// CSV: one header line (the column names), then one line per point; attribute names containing a comma,
// quote or line break are quoted (RFC 4180).
// PLY: "format ascii 1.0" with one vertex element whose properties are the columns (float, class int);
// attribute names must then be single words (letters, digits, '_', '-', '.').
// Attribute names may not repeat a fixed column's name. Not atomic by itself. Throws FileError on failure.
void write_points_file(const Points& points, const std::filesystem::path& path, PointsFormat format,
                       const WriteProgress& progress = {});

}  // namespace orogen
