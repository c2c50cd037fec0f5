#include "nodes/io/curves_file.h"
#include "nodes/io/file_extension.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "graph/checked_file.h"

namespace orogen {
namespace {

void put(std::string& s, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

}  // namespace

std::optional<CurvesFormat> curves_format_from_path(const std::filesystem::path& path) {
  const std::string e = lower_extension(path);
  if (e == ".json" || e == ".geojson") return CurvesFormat::Json;
  if (e == ".obj") return CurvesFormat::Obj;
  return std::nullopt;
}

void write_curves_file(const Curves& curves, const std::filesystem::path& path, CurvesFormat format,
                       const WriteProgress& progress) {
  try {
    curves.check_consistent();
  } catch (const std::logic_error& e) {
    throw FileError(path.string() + ": inconsistent curves: " + e.what());
  }
  std::string text;
  const std::size_t n = curves.size();
  if (format == CurvesFormat::Json) {
    // Assembled by hand (numbers via to_chars) so large networks stay fast; names escaped by nlohmann.
    text += "{\"type\":\"FeatureCollection\",\"features\":[";
    for (std::size_t k = 0; k < n; ++k) {
      const Curve& c = curves.curves[k];
      if (k) text += ",";
      text += "\n{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[";
      for (std::size_t v = 0; v < c.points.size(); ++v) {
        text += v ? ",[" : "[";
        put(text, c.points[v].x), text += ",", put(text, c.points[v].y), text += ",", put(text, c.points[v].z);
        text += "]";
      }
      text += "]},\"properties\":{\"index\":" + std::to_string(k) + ",\"parent\":" + std::to_string(c.parent) +
              ",\"width\":[";
      for (std::size_t v = 0; v < c.width.size(); ++v) {
        if (v) text += ",";
        put(text, c.width[v]);
      }
      text += "]";
      for (const auto& [name, values] : c.attributes) {
        if (name == "index" || name == "parent" || name == "width")
          throw FileError(path.string() + ": attribute name '" + name + "' is reserved");
        text += ",";
        text += nlohmann::json(name).dump();
        text += ":[";
        for (std::size_t v = 0; v < values.size(); ++v) {
          if (v) text += ",";
          put(text, values[v]);
        }
        text += "]";
      }
      text += "}}";
      if (progress && (k & 255) == 0) progress(0.9 * static_cast<double>(k) / static_cast<double>(n));
    }
    text += "\n]}\n";
  } else {
    text += "# Orogen curves: " + std::to_string(n) + " polylines, world metres, z up\n";
    std::size_t base = 1;
    for (std::size_t k = 0; k < n; ++k) {
      const Curve& c = curves.curves[k];
      text +=
          "g curve_" + std::to_string(k) + "\n# parent " + std::to_string(k) + " " + std::to_string(c.parent) + "\n";
      for (const auto& v : c.points) {
        text += "v ";
        put(text, v.x), text += " ", put(text, v.y), text += " ", put(text, v.z);
        text += "\n";
      }
      auto attr = [&](const std::string& name, const std::vector<float>& values) {
        for (char ch : name)
          if (std::isspace(static_cast<unsigned char>(ch)))
            throw FileError(path.string() + ": attribute name '" + name + "' contains white space");
        text += "# attr " + name;
        for (float x : values) text += " ", put(text, x);
        text += "\n";
      };
      attr("width", c.width);
      for (const auto& [name, values] : c.attributes) attr(name, values);
      if (c.points.size() >= 2) {
        text += "l";
        for (std::size_t v = 0; v < c.points.size(); ++v) {
          text += ' ';
          text += std::to_string(base + v);
        }
        text += "\n";
      }
      base += c.points.size();
      if (progress && (k & 255) == 0) progress(0.9 * static_cast<double>(k) / static_cast<double>(n));
    }
  }
  try {
    CheckedFile f(path);  // every write checked, synced before the rename (a full disk fails the node)
    // Written in blocks of 1 MiB, each followed by a progress report (which polls the cancel flag).
    constexpr std::size_t kBlock = std::size_t{1} << 20;
    for (std::size_t at = 0; at < text.size(); at += kBlock) {
      if (!f.write(text.data() + at, std::min(kBlock, text.size() - at))) break;
      if (progress)
        progress(0.9 + 0.09 * std::min(1.0, static_cast<double>(at + kBlock) / static_cast<double>(text.size())));
    }
    f.finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  if (progress) progress(1.0);
}

}  // namespace orogen
