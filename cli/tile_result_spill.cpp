#include "cli/tile_result_spill.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "evaluator/value_serialization.h"

namespace orogen::cli {
namespace {

namespace fs = std::filesystem;

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(errno));
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_error = wrote ? 0 : errno;
  if (std::fclose(f) != 0 || !wrote) {
    const int e = write_error ? write_error : errno;
    std::error_code ignored;
    fs::remove(path, ignored);
    throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(e));
  }
}

std::string read_bytes(const fs::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot read '" + path.string() + "': " + std::strerror(errno));
  std::string bytes;
  char buffer[1 << 16];
  std::size_t n;
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (!ec) bytes.reserve(static_cast<std::size_t>(size));
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) bytes.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw std::runtime_error("cannot read '" + path.string() + "'");
  return bytes;
}

}  // namespace

TileResultSpill::TileResultSpill(const fs::path& folder) {
  const fs::path base = folder.empty() ? fs::path(".") : folder;
  std::error_code ec;
  fs::create_directories(base, ec);
  lock_ = std::make_unique<TemporaryLock>(base);
  directory_ = base / (std::string(kTemporaryPrefix) + lock_->tag() + ".stages");
  if (!fs::create_directory(directory_, ec) || ec)
    throw std::runtime_error("cannot create '" + directory_.string() + "': " + ec.message());
}

TileResultSpill::~TileResultSpill() {
  std::error_code ignored;
  fs::remove_all(directory_, ignored);
  // lock_ goes after the directory: a sweep that finds the directory finds its owner alive.
}

fs::path TileResultSpill::file(std::size_t tile, const std::string& node) const {
  // Node ids are graph identifiers, but an instance's inner nodes hold '/': keep file names flat.
  std::string name = std::to_string(tile) + "-";
  for (const char c : node) name += c == '/' ? '~' : c;
  return directory_ / name;
}

void TileResultSpill::put(std::size_t tile, const std::string& node, const CachedResult& result) {
  ByteWriter w;
  w.u64(result.outputs.size());
  for (const auto& v : result.outputs) write_value(w, v);
  write_bytes(file(tile, node), w.buffer());
  written_ += w.buffer().size();
  nodes_[tile].insert(node);
}

std::shared_ptr<const CachedResult> TileResultSpill::get(std::size_t tile, const std::string& node) const {
  const auto it = nodes_.find(tile);
  if (it == nodes_.end() || !it->second.count(node))
    throw std::runtime_error("no kept result of node '" + node + "' on tile " + std::to_string(tile));
  const fs::path path = file(tile, node);
  const std::string bytes = read_bytes(path);
  try {
    ByteReader r(bytes);
    auto result = std::make_shared<CachedResult>();
    result->outputs.resize(r.count(1));
    for (auto& v : result->outputs) v = read_value(r);
    if (!r.at_end()) throw SerializationError("trailing bytes");
    return result;
  } catch (const SerializationError& e) {
    throw std::runtime_error("'" + path.string() + "' is damaged: " + e.what());
  }
}

std::map<std::string, std::shared_ptr<const CachedResult>> TileResultSpill::take(std::size_t tile) {
  std::map<std::string, std::shared_ptr<const CachedResult>> results;
  for (const auto& node : nodes(tile)) {
    results[node] = get(tile, node);
    std::error_code ignored;
    fs::remove(file(tile, node), ignored);
  }
  nodes_.erase(tile);
  return results;
}

std::set<std::string> TileResultSpill::nodes(std::size_t tile) const {
  const auto it = nodes_.find(tile);
  return it == nodes_.end() ? std::set<std::string>{} : it->second;
}

}  // namespace orogen::cli
