#include "cli/join_tiles.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "nodes/io/block_writer.h"

namespace orogen::cli {

namespace {

namespace fs = std::filesystem;

std::ifstream open_tile(const fs::path& tile) {
  std::ifstream in(tile, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read the tile " + tile.string());
  return in;
}

[[noreturn]] void unexpected(const fs::path& tile, const std::string& what) {
  throw std::runtime_error("the tile " + tile.string() + " " + what + ": was it written by this build?");
}

long long parse_integer(const std::string& text, std::size_t& at, const fs::path& tile) {
  long long v = 0;
  const auto r = std::from_chars(text.data() + at, text.data() + text.size(), v);
  if (r.ec != std::errc()) unexpected(tile, "has a line Orogen does not write: " + text.substr(0, 80));
  at = static_cast<std::size_t>(r.ptr - text.data());
  return v;
}

// Whether a point's line (its first two fields x and y, split by `separator`) lies on a shared line of samples.
bool on_border(const std::string& line, char separator, const std::vector<double>& border_x,
               const std::vector<double>& border_y) {
  float xy[2];
  const char* p = line.data();
  const char* end = line.data() + line.size();
  for (float& v : xy) {
    const auto r = std::from_chars(p, end, v);
    if (r.ec != std::errc()) return false;
    p = r.ptr;
    if (p < end && *p == separator) ++p;
  }
  const auto hits = [](float v, const std::vector<double>& lines) {
    return std::any_of(lines.begin(), lines.end(), [v](double b) { return static_cast<float>(b) == v; });
  };
  return hits(xy[0], border_x) || hits(xy[1], border_y);
}

// The rows of every tile after its `header_lines` lines, each once if on a border, to `row` in tile order.
template <class Row>
void for_each_point_row(const std::vector<fs::path>& tiles, std::size_t header_lines, char separator,
                        const std::vector<double>& border_x, const std::vector<double>& border_y, Row row) {
  std::unordered_set<std::string> seen;  // rows on shared lines of samples, the only ones two tiles can write
  std::string line;
  for (const auto& tile : tiles) {
    std::ifstream in = open_tile(tile);
    for (std::size_t k = 0; k < header_lines; ++k) std::getline(in, line);
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (on_border(line, separator, border_x, border_y) && !seen.insert(line).second) continue;
      row(line);
    }
  }
}

// A PLY file's header lines up to end_header, with the vertex count taken out (`count` gets it).
std::vector<std::string> ply_header(const fs::path& tile, long long& count) {
  std::ifstream in = open_tile(tile);
  std::vector<std::string> lines;
  std::string line;
  count = -1;
  while (std::getline(in, line)) {
    if (line.rfind("element vertex ", 0) == 0) {
      std::size_t at = 15;
      count = parse_integer(line, at, tile);
      line = "element vertex";
    }
    lines.push_back(line);
    if (line == "end_header") break;
  }
  if (lines.empty() || lines.front() != "ply" || lines.back() != "end_header" || count < 0)
    unexpected(tile, "is not an ASCII PLY of points");
  return lines;
}

void put_line(BlockWriter& out, const std::string& line) {
  out.put(line);
  out.put("\n");
}

}  // namespace

void join_points_csv(const std::vector<fs::path>& tiles, const fs::path& target, const std::vector<double>& border_x,
                     const std::vector<double>& border_y) {
  std::string header;
  std::getline(open_tile(tiles.front()), header);
  for (const auto& tile : tiles) {
    std::string h;
    std::getline(open_tile(tile), h);
    if (h != header) unexpected(tile, "has other columns than " + tiles.front().string());
  }
  BlockWriter out(target);
  put_line(out, header);
  for_each_point_row(tiles, 1, ',', border_x, border_y, [&](const std::string& row) { put_line(out, row); });
  out.finish();
}

void join_points_ply(const std::vector<fs::path>& tiles, const fs::path& target, const std::vector<double>& border_x,
                     const std::vector<double>& border_y) {
  long long count = 0;
  const std::vector<std::string> header = ply_header(tiles.front(), count);
  for (const auto& tile : tiles)
    if (ply_header(tile, count) != header) unexpected(tile, "has other properties than " + tiles.front().string());
  // The header states the count: a first pass counts the points kept.
  long long total = 0;
  for_each_point_row(tiles, header.size(), ' ', border_x, border_y, [&](const std::string&) { ++total; });
  BlockWriter out(target);
  for (const auto& line : header) put_line(out, line == "element vertex" ? line + " " + std::to_string(total) : line);
  for_each_point_row(tiles, header.size(), ' ', border_x, border_y,
                     [&](const std::string& row) { put_line(out, row); });
  out.finish();
}

void join_curves_json(const std::vector<fs::path>& tiles, const fs::path& target) {
  static const std::string kOpen = "{\"type\":\"FeatureCollection\",\"features\":[";
  static const std::string kIndex = "\"properties\":{\"index\":";
  static const std::string kParent = ",\"parent\":";
  BlockWriter out(target);
  out.put(kOpen);
  long long written = 0;
  std::string line;
  for (const auto& tile : tiles) {
    std::ifstream in = open_tile(tile);
    if (!std::getline(in, line) || line != kOpen) unexpected(tile, "is not a curves file Orogen wrote");
    const long long offset = written;
    bool closed = false;
    while (std::getline(in, line)) {
      if (line == "]}") {
        closed = true;
        break;
      }
      if (!line.empty() && line.back() == ',') line.pop_back();
      // {"type":"Feature",...,"properties":{"index":K,"parent":P,...}}: K and P move by the curves before.
      std::size_t at = line.find(kIndex);
      if (at == std::string::npos) unexpected(tile, "has a feature without its index");
      at += kIndex.size();
      const std::size_t index_at = at;
      const long long index = parse_integer(line, at, tile);
      if (line.compare(at, kParent.size(), kParent) != 0) unexpected(tile, "has a feature without its parent");
      std::size_t parent_end = at + kParent.size();
      const long long parent = parse_integer(line, parent_end, tile);
      out.put(written == 0 ? "\n" : ",\n");
      out.put(line.substr(0, index_at));
      out.put(std::to_string(index + offset) + kParent + std::to_string(parent < 0 ? parent : parent + offset));
      out.put(line.substr(parent_end));
      ++written;
    }
    if (!closed) unexpected(tile, "ends before its last curve");
  }
  out.put("\n]}\n");
  out.finish();
}

void join_curves_obj(const std::vector<fs::path>& tiles, const fs::path& target) {
  static const std::string kHeader = "# Orogen curves: ";
  static const std::string kHeaderEnd = " polylines, world metres, z up";
  long long total = 0;
  std::string line;
  for (const auto& tile : tiles) {
    if (!std::getline(open_tile(tile), line) || line.rfind(kHeader, 0) != 0) unexpected(tile, "has no curves header");
    std::size_t at = kHeader.size();
    total += parse_integer(line, at, tile);
  }
  BlockWriter out(target);
  put_line(out, kHeader + std::to_string(total) + kHeaderEnd);
  long long curves = 0, vertices = 0;
  for (const auto& tile : tiles) {
    std::ifstream in = open_tile(tile);
    std::getline(in, line);
    const long long curve_offset = curves, vertex_offset = vertices;
    while (std::getline(in, line)) {
      if (line.rfind("g curve_", 0) == 0) {
        std::size_t at = 8;
        put_line(out, "g curve_" + std::to_string(parse_integer(line, at, tile) + curve_offset));
        ++curves;
      } else if (line.rfind("# parent ", 0) == 0) {
        std::size_t at = 9;
        const long long k = parse_integer(line, at, tile);
        ++at;
        const long long parent = parse_integer(line, at, tile);
        put_line(out, "# parent " + std::to_string(k + curve_offset) + " " +
                          std::to_string(parent < 0 ? parent : parent + curve_offset));
      } else if (line.rfind("l ", 0) == 0) {
        std::string moved = "l";
        std::size_t at = 1;
        while (at < line.size()) {
          ++at;  // the space
          moved += " " + std::to_string(parse_integer(line, at, tile) + vertex_offset);
        }
        put_line(out, moved);
      } else {
        if (line.rfind("v ", 0) == 0) ++vertices;
        put_line(out, line);
      }
    }
  }
  out.finish();
}

}  // namespace orogen::cli
