#include "nodes/io/points_file.h"
#include "nodes/io/file_extension.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <memory>
#include <string>

#include "graph/checked_file.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 11> kColumns{"x", "y", "z", "qw", "qx", "qy", "qz", "sx", "sy", "sz", "class"};

void append_number(std::string& line, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  line.append(buf, r.ptr);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

bool is_ply_word(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(),
                                   [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-' || c == '.'; });
}

void check_names(const Points& points, PointsFormat format, const fs::path& path) {
  for (const auto& [name, values] : points.attributes) {
    // A named reference: clang 14 cannot capture a structured binding in a lambda.
    const std::string& attribute = name;
    if (std::find_if(kColumns.begin(), kColumns.end(), [&](const char* c) { return attribute == c; }) != kColumns.end())
      throw FileError("cannot write '" + path.string() + "': attribute '" + name + "' has the name of a fixed column");
    if (name.empty()) throw FileError("cannot write '" + path.string() + "': an attribute has an empty name");
    if (format == PointsFormat::Ply && !is_ply_word(name))
      throw FileError("cannot write '" + path.string() + "': attribute '" + name +
                      "' is not a valid PLY property name (use letters, digits, '_', '-', '.')");
  }
}

}  // namespace

std::optional<PointsFormat> points_format_from_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".csv") return PointsFormat::Csv;
  if (ext == ".ply") return PointsFormat::Ply;
  return std::nullopt;
}

void write_points_file(const Points& points, const fs::path& path, PointsFormat format, const WriteProgress& progress) {
  try {
    points.check_consistent();
  } catch (const std::logic_error& e) {
    throw FileError("cannot write '" + path.string() + "': " + e.what());
  }
  check_names(points, format, path);
  std::unique_ptr<CheckedOStream> stream;
  try {
    stream = std::make_unique<CheckedOStream>(path);
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  CheckedOStream& out = *stream;

  std::string line;
  if (format == PointsFormat::Csv) {
    for (const char* c : kColumns) {
      if (!line.empty()) line += ',';
      line += c;
    }
    for (const auto& [name, values] : points.attributes) {
      line += ',';
      line += csv_field(name);
    }
  } else {
    line =
        "ply\nformat ascii 1.0\ncomment Orogen points: position in metres (z up), rotation quaternion, scale, "
        "class id, attributes\nelement vertex " +
        std::to_string(points.size()) + "\n";
    for (const char* c : kColumns) {
      line += std::string_view(c) == "class" ? "property int " : "property float ";
      line += c;
      line += '\n';
    }
    for (const auto& [name, values] : points.attributes) {
      line += "property float ";
      line += name;
      line += '\n';
    }
    line += "end_header";
  }
  line += '\n';
  out << line;

  const char sep = format == PointsFormat::Csv ? ',' : ' ';
  const std::size_t n = points.size();
  for (std::size_t k = 0; k < n; ++k) {
    line.clear();
    const auto& p = points.position[k];
    const auto& q = points.rotation[k];
    const auto& s = points.scale[k];
    for (float v : {p.x, p.y, p.z, q.w, q.x, q.y, q.z, s.x, s.y, s.z}) {
      append_number(line, v);
      line += sep;
    }
    line += std::to_string(points.class_id[k]);
    for (const auto& [name, values] : points.attributes) {
      line += sep;
      append_number(line, values[k]);
    }
    line += '\n';
    out << line;
    if (progress && (k + 1) % 4096 == 0) {
      if (!out) break;
      progress(static_cast<double>(k + 1) / static_cast<double>(n));
    }
  }
  if (progress) progress(0.95);  // every line is written; a cancel here skips the sync and the rename
  try {
    out.finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  if (progress) progress(1.0);
}

}  // namespace orogen
