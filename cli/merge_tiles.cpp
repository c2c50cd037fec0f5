#include "cli/merge_tiles.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli/join_tiles.h"
#include "cli/tiling.h"
#include "graph/atomic_file.h"
#include "graph/checked_file.h"
#include "nodes/io/block_rows.h"
#include "nodes/io/block_writer.h"
#include "nodes/io/checked_image_output.h"
#include "nodes/io/curves_file.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/georeference.h"
#include "nodes/io/height_sidecar.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_codec.h"
#include "nodes/io/image_file.h"
#include "nodes/io/points_file.h"

namespace orogen::cli {

namespace {

namespace fs = std::filesystem;

template <class T>
const T& param(const Graph& graph, const std::string& node, const char* name) {
  return std::get<T>(graph.param(node, name));
}

bool sixteen_bit(HeightFormat f) { return f == HeightFormat::Png16 || f == HeightFormat::Raw16; }

// Rows [y0, y1) (north first) of one tile's file, every channel, in the file's sample type, packed.
class TileRows {
 public:
  virtual ~TileRows() = default;
  virtual void read(int y0, int y1, unsigned char* out) = 0;
};

class ImageTileRows final : public TileRows {
 public:
  ImageTileRows(const fs::path& path, const TileWindow& w, const ImageWriteSpec& spec) : path_(path) {
    std::string error;
    in_ = image_codec().open_reader(path.string(), error);
    if (!in_) throw std::runtime_error("cannot read the tile " + path.string() + ": " + error);
    const ImageInfo& info = in_->info();
    bool same_type = true;
    for (PixelType t : info.channel_types) same_type = same_type && t == spec.type;
    if (info.width != w.size.x || info.height != w.size.y || info.channels != spec.channels || !same_type)
      throw std::runtime_error("the tile " + path.string() + " is " + std::to_string(info.width) + "x" +
                               std::to_string(info.height) + " with " + std::to_string(info.channels) + " " +
                               info.format_text + " channels, not the " + std::to_string(w.size.x) + "x" +
                               std::to_string(w.size.y) + " its window and writer give: was it written by this build?");
  }
  void read(int y0, int y1, unsigned char* out) override {
    if (!in_->read_native_scanlines(y0, y1, 0, in_->info().channels, out))
      throw std::runtime_error("cannot read the tile " + path_.string() + ": " + in_->error());
  }

 private:
  fs::path path_;
  std::unique_ptr<ImageReader> in_;
};

class RawTileRows final : public TileRows {
 public:
  RawTileRows(const fs::path& path, const TileWindow& w) : path_(path), row_bytes_(std::size_t(w.size.x) * 2) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec || size != row_bytes_ * std::size_t(w.size.y))
      throw std::runtime_error("the tile " + path.string() + " is not the " + std::to_string(w.size.x) + "x" +
                               std::to_string(w.size.y) +
                               " RAW16 file its window gives: was it written by this build?");
    in_.open(path, std::ios::binary);
    if (!in_) throw std::runtime_error("cannot read the tile " + path.string());
  }
  void read(int y0, int y1, unsigned char* out) override {
    in_.seekg(static_cast<std::streamoff>(row_bytes_ * std::size_t(y0)));
    in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(row_bytes_ * std::size_t(y1 - y0)));
    if (!in_) throw std::runtime_error("cannot read the tile " + path_.string());
  }

 private:
  fs::path path_;
  std::size_t row_bytes_;
  std::ifstream in_;
};

// The files of the tiles of a writer of `path` (resolved: `target`), tile (I, J) at I + J N.
std::vector<fs::path> tile_files(const fs::path& target, const std::string& path, glm::ivec2 counts,
                                 TileNaming naming) {
  std::vector<fs::path> tiles;
  for (int j = 0; j < counts.y; ++j)
    for (int i = 0; i < counts.x; ++i)
      tiles.push_back(target.parent_path() /
                      fs::path(with_suffix(path, tile_suffix(named_tile_index(naming, {i, j}, counts)))).filename());
  return tiles;
}

// Whether the files hold the same bytes (compared a block at a time).
bool same_files(const std::vector<fs::path>& files) {
  std::error_code ec;
  const auto size = fs::file_size(files.front(), ec);
  if (ec) throw std::runtime_error("cannot read the tile " + files.front().string() + ": " + ec.message());
  for (std::size_t k = 1; k < files.size(); ++k)
    if (fs::file_size(files[k], ec) != size || ec) return false;
  std::vector<char> first(1 << 16), other(1 << 16);
  std::ifstream a(files.front(), std::ios::binary);
  for (std::size_t k = 1; k < files.size(); ++k) {
    std::ifstream b(files[k], std::ios::binary);
    a.clear();
    a.seekg(0);
    while (a && b) {
      a.read(first.data(), static_cast<std::streamsize>(first.size()));
      b.read(other.data(), static_cast<std::streamsize>(other.size()));
      if (a.gcount() != b.gcount() || !std::equal(first.begin(), first.begin() + a.gcount(), other.begin()))
        return false;
    }
  }
  return true;
}

// One raster writer's merge: its tiles, how to read them and the merged file's header.
struct RasterMerge {
  std::string node;
  fs::path target;                     // the merged file
  std::vector<fs::path> tiles;         // tile (I, J) at I + J N
  std::optional<ImageWriteSpec> spec;  // empty: RAW16
  std::size_t pixel_bytes = 2;
  std::vector<AtomicWrite> side_files;  // written with the merged file
};

// The merged rows, north first, a band at a time: each band is put together from the tiles of the tile rows
// it crosses (shared border samples are equal: the later tile overwrites them), then handed to `write`.
void stream_rows(const RasterMerge& m, const Domain& full, glm::ivec2 counts,
                 const std::function<void(int r0, int r1, const unsigned char* rows)>& write) {
  const int width = full.resolution.x, height = full.resolution.y;
  const std::size_t row_bytes = std::size_t(width) * m.pixel_bytes;
  const int band_rows = block_rows(height);  // the untiled writer's blocks: the same calls into the codec
  std::vector<unsigned char> band, piece;
  int open_row = -1;  // the tile row whose tiles are open
  std::vector<std::unique_ptr<TileRows>> open;
  std::vector<TileWindow> windows;
  for (int r0 = 0; r0 < height; r0 += band_rows) {
    const int r1 = std::min(r0 + band_rows, height);
    band.resize(std::size_t(r1 - r0) * row_bytes);
    int r = r0;
    while (r < r1) {
      // Heightfield row height - 1 - r; the tile rows from the north, the first one holding it.
      const int y = height - 1 - r;
      int j = counts.y - 1;
      while (j > 0 && tile_window(full.resolution, counts, {0, j}).first.y > y) --j;
      if (j != open_row) {
        open.clear();
        windows.clear();
        for (int i = 0; i < counts.x; ++i) {
          const TileWindow w = tile_window(full.resolution, counts, {i, j});
          const fs::path& path = m.tiles[std::size_t(j * counts.x + i)];
          if (m.spec)
            open.push_back(std::make_unique<ImageTileRows>(path, w, *m.spec));
          else
            open.push_back(std::make_unique<RawTileRows>(path, w));
          windows.push_back(w);
        }
        open_row = j;
      }
      const TileWindow& w0 = windows.front();
      const int top = height - (w0.first.y + w0.size.y);  // the file row of this tile row's northern row
      const int end = std::min(r1, top + w0.size.y);
      for (int i = 0; i < counts.x; ++i) {
        const TileWindow& w = windows[std::size_t(i)];
        const std::size_t tile_row_bytes = std::size_t(w.size.x) * m.pixel_bytes;
        piece.resize(std::size_t(end - r) * tile_row_bytes);
        open[std::size_t(i)]->read(r - top, end - top, piece.data());
        for (int k = r; k < end; ++k)
          std::memcpy(band.data() + std::size_t(k - r0) * row_bytes + std::size_t(w.first.x) * m.pixel_bytes,
                      piece.data() + std::size_t(k - r) * tile_row_bytes, tile_row_bytes);
      }
      r = end;
    }
    write(r0, r1, band.data());
  }
}

void write_merged(const RasterMerge& m, const Domain& full, glm::ivec2 counts, const fs::path& temporary) {
  if (!m.spec) {
    BlockWriter out(temporary);
    stream_rows(m, full, counts, [&](int r0, int r1, const unsigned char* rows) {
      out.put(rows, std::size_t(r1 - r0) * std::size_t(full.resolution.x) * 2);
    });
    out.finish();
    return;
  }
  CheckedImageSink sink(temporary);
  std::string error;
  // The target's name gives the format (the temporary's extension is not the target's).
  auto out = create_checked_output(m.target, sink, *m.spec, error);
  if (!out) throw std::runtime_error("cannot create " + m.target.string() + ": " + error);
  const auto row_stride = static_cast<std::ptrdiff_t>(std::size_t(full.resolution.x) * m.pixel_bytes);
  stream_rows(m, full, counts, [&](int r0, int r1, const unsigned char* rows) {
    if (!out->write_rows(r0, r1, rows, row_stride))
      throw std::runtime_error(sink.file().ok() ? "cannot write " + m.target.string() + ": " + out->error()
                                                : sink.file().error());
  });
  const bool closed = out->close();
  if (!sink.file().ok()) throw std::runtime_error(sink.file().error());
  if (!closed) throw std::runtime_error("cannot finish " + m.target.string() + ": " + out->error());
  sink.file().finish();
}

// The merge of one writer, or nullopt with `why` set when it keeps its tiles.
std::optional<RasterMerge> plan_merge(const Graph& graph, const Node& node, const Domain& full, glm::ivec2 counts,
                                      TileNaming naming, const OutputPolicy& policy, std::string& why) {
  const std::string& type = node.type->name;
  if (type != "WriteHeightfield" && type != "WriteImage") {
    why = type + " files are not merged";
    return std::nullopt;
  }
  const std::string& path = param<std::string>(graph, node.id, "path");
  RasterMerge m;
  m.node = node.id;
  m.target = resolve_output_path(policy, path);
  m.tiles = tile_files(m.target, path, counts, naming);
  if (type == "WriteImage") {
    ImageWriteOptions options;
    options.format = image_format_from_path(path).value();  // the tiles were written: the extension is known
    if (options.format == ImageFormat::Png8 && param<std::string>(graph, node.id, "bit_depth") == "16")
      options.format = ImageFormat::Png16;
    options.compression_level = static_cast<int>(param<std::int64_t>(graph, node.id, "compression_level"));
    // Color or data, and the channels' names, belong to the image, not to the writer: the tiles' files say.
    std::string error;
    const auto first = image_codec().open_reader(m.tiles.front().string(), error);
    if (!first) throw std::runtime_error("cannot read the tile " + m.tiles.front().string() + ": " + error);
    options.srgb = first->string_attribute("oiio:ColorSpace") == "sRGB";
    const ImageInfo& info = first->info();
    m.spec = image_file_spec(full.width(), full.height(), info.channels, info.channel_names, options);
    m.pixel_bytes = pixel_type_size(m.spec->type) * std::size_t(info.channels);
    return m;
  }
  HeightfieldWriteOptions options;
  options.format = height_format_from_path(path).value();  // the tiles were written: the extension is known
  options.compression_level = static_cast<int>(param<std::int64_t>(graph, node.id, "compression_level"));
  options.exr_compression = param<std::string>(graph, node.id, "exr_compression");
  std::optional<HeightRange> range;
  if (sixteen_bit(options.format))
    range = HeightRange{param<double>(graph, node.id, "height_min"), param<double>(graph, node.id, "height_max")};
  if (options.format != HeightFormat::Raw16) {
    m.spec = heightfield_image_spec(full, options, range);
    m.pixel_bytes = pixel_type_size(m.spec->type);
  }
  const std::string file_name = m.target.filename().string();
  if (range) {
    const std::string text = height_sidecar_json(full, options.format, *range, file_name);
    m.side_files.push_back({fs::path(m.target) += ".json", [text](const fs::path& t) { write_text_file(t, text); }});
  }
  if (const auto& crs = param<std::string>(graph, node.id, "crs"); !crs.empty()) {
    const std::string text = gdal_pam_xml(full, crs);
    m.side_files.push_back({fs::path(m.target) += ".aux.xml", [text](const fs::path& t) { write_text_file(t, text); }});
  }
  return m;
}

bool writes_rasters(const NodeType& type) {
  if (!type.writes_files || type.own_lattice) return false;
  for (const auto& p : type.inputs)
    if (p.type == PortType::Heightfield || p.type == PortType::Image) return true;
  return false;
}

}  // namespace

std::vector<std::string> merge_errors(const Graph& graph) {
  std::vector<std::string> errors;
  for (const auto& node : graph.nodes()) {
    if (node.type->name != "WriteHeightfield") continue;
    const auto format = height_format_from_path(param<std::string>(graph, node.id, "path"));
    if (format && sixteen_bit(*format) && param<std::string>(graph, node.id, "range") != "fixed")
      errors.push_back("--merge: '" + node.id + "' writes 16-bit heights with range 'auto', so each tile maps its " +
                       "own range and the tiles cannot join into one file; set range 'fixed' with height_min and " +
                       "height_max, or write EXR or TIFF (float metres)");
  }
  return errors;
}

MergeResult merge_tiles(const Graph& graph, const Domain& full, glm::ivec2 counts, TileNaming naming,
                        const OutputPolicy& policy, const std::function<void(const std::string&)>& starting) {
  MergeResult result;
  // The lines of samples neighboring tiles share: only points on them can be written by two tiles.
  std::vector<double> border_x, border_y;
  for (int i = 1; i < counts.x; ++i) border_x.push_back(full.x(tile_window(full.resolution, counts, {i, 0}).first.x));
  for (int j = 1; j < counts.y; ++j) border_y.push_back(full.y(tile_window(full.resolution, counts, {0, j}).first.y));
  const auto replace = [&](const Node& node, const fs::path& target, const std::vector<fs::path>& tiles,
                           std::vector<AtomicWrite> files) {
    if (starting) starting(target.string());
    write_files_atomically(files);
    // The merged file replaces the tiles, their side files and a mosaic of them left by an earlier build.
    std::error_code ignored;
    for (const auto& tile : tiles)
      for (const char* extra : {"", ".json", ".aux.xml"}) fs::remove(fs::path(tile) += extra, ignored);
    fs::remove(fs::path(target).replace_extension(".vrt"), ignored);
    result.files.push_back(target.string());
    result.merged_nodes.insert(node.id);
  };
  for (const auto& node : graph.nodes()) {
    if (!node.type->writes_files) continue;
    const std::string& type = node.type->name;
    if (type == "WritePoints" || type == "WriteCurves") {
      const std::string& path = param<std::string>(graph, node.id, "path");
      const fs::path target = resolve_output_path(policy, path);
      const std::vector<fs::path> tiles = tile_files(target, path, counts, naming);
      std::function<void(const fs::path&)> join;
      if (type == "WritePoints")
        join = [&, ply = points_format_from_path(path) == PointsFormat::Ply](const fs::path& out) {
          ply ? join_points_ply(tiles, out, border_x, border_y) : join_points_csv(tiles, out, border_x, border_y);
        };
      else
        join = [&, obj = curves_format_from_path(path) == CurvesFormat::Obj](const fs::path& out) {
          obj ? join_curves_obj(tiles, out) : join_curves_json(tiles, out);
        };
      // A value every tile computes whole (a replicated river network) is in every tile's file: written once.
      if (same_files(tiles)) join = [&](const fs::path& out) { fs::copy_file(tiles.front(), out); };
      replace(node, target, tiles, {{target, join}});
      continue;
    }
    if (!writes_rasters(*node.type)) {
      result.warnings.push_back("'" + node.id + "' keeps its tiles: " + type + " files are not merged");
      continue;
    }
    std::string why;
    const auto m = plan_merge(graph, node, full, counts, naming, policy, why);
    if (!m) {
      result.warnings.push_back("'" + node.id + "' keeps its tiles: " + why);
      continue;
    }
    std::vector<AtomicWrite> files;
    files.push_back({m->target, [&](const fs::path& temporary) { write_merged(*m, full, counts, temporary); }});
    for (const auto& f : m->side_files) files.push_back(f);
    replace(node, m->target, m->tiles, std::move(files));
  }
  return result;
}

}  // namespace orogen::cli
