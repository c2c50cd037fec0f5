#include "evaluator/disk_cache.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include <xxhash.h>

#include "evaluator/value_serialization.h"
#include "graph/atomic_file.h"

namespace orogen {
namespace {

constexpr char kMagic[8] = {'O', 'R', 'O', 'G', 'E', 'N', 'C', '1'};
constexpr std::uint32_t kContainerVersion = 1;

std::string encode_payload(const CachedResult& result) {
  ByteWriter w;
  w.u64(result.outputs.size());
  for (const auto& v : result.outputs) write_value(w, v);
  w.u64(result.files.size());
  for (const auto& f : result.files) {
    w.str(f.path.generic_string());
    w.u64(f.size);
    w.i64(f.mtime_ns);
  }
  return w.take();
}

std::shared_ptr<CachedResult> decode_payload(std::string_view payload) {
  ByteReader r(payload);
  auto result = std::make_shared<CachedResult>();
  result->outputs.resize(r.count(1));
  for (auto& v : result->outputs) v = read_value(r);
  result->files.resize(r.count(24));
  for (auto& f : result->files) {
    f.path = r.str();
    f.size = r.u64();
    f.mtime_ns = r.i64();
  }
  if (!r.at_end()) throw SerializationError("trailing bytes after the payload");
  return result;
}

}  // namespace

std::filesystem::path DiskCache::path_of(const CacheKey& key) const {
  const auto hex = key.hex();
  return dir_ / hex.substr(0, 2) / (hex + ".orc");
}

void DiskCache::store(const CacheKey& key, const CachedResult& result) const {
  const std::string payload = encode_payload(result);
  ByteWriter header;
  header.raw(kMagic, sizeof kMagic);
  header.u32(kContainerVersion);
  header.u32(kValueFormatVersion);
  header.u64(key.high);
  header.u64(key.low);
  header.u64(payload.size());
  header.u64(XXH3_64bits(payload.data(), payload.size()));
  if (header.buffer().size() != kHeaderBytes) throw std::logic_error("disk cache header size");
  write_file_atomically(path_of(key), [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create cache file " + temporary.string());
    out.write(header.buffer().data(), static_cast<std::streamsize>(header.buffer().size()));
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write cache file " + temporary.string());
  });
}

void DiskCache::remove(const CacheKey& key) const {
  std::error_code ignored;
  std::filesystem::remove(path_of(key), ignored);
}

DiskCache::Loaded DiskCache::load(const CacheKey& key) const {
  Loaded loaded;
  const auto path = path_of(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return loaded;  // a miss
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool read_failed = in.bad();
  in.close();

  auto reject = [&](std::string why) {
    remove(key);
    loaded.result = nullptr;
    loaded.rejected = true;
    loaded.reason = path.string() + ": " + std::move(why);
    return loaded;
  };
  if (read_failed) return reject("read error");
  if (bytes.size() < kHeaderBytes) return reject("truncated header");
  ByteReader header(std::string_view(bytes).substr(0, kHeaderBytes));
  char magic[sizeof kMagic];
  header.raw(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) return reject("not an Orogen cache file");
  if (header.u32() != kContainerVersion) return reject("other container format version");
  if (header.u32() != kValueFormatVersion) return reject("other value format version");
  CacheKey stored;
  stored.high = header.u64();
  stored.low = header.u64();
  if (!(stored == key)) return reject("filed under the wrong key");
  const std::uint64_t length = header.u64();
  const std::uint64_t checksum = header.u64();
  const std::string_view payload = std::string_view(bytes).substr(kHeaderBytes);
  if (payload.size() != length) return reject("payload length differs from the header (truncated?)");
  if (XXH3_64bits(payload.data(), payload.size()) != checksum) return reject("checksum mismatch");
  try {
    loaded.result = decode_payload(payload);
  } catch (const std::exception& e) {
    return reject(std::string("undecodable payload: ") + e.what());
  }
  return loaded;
}

}  // namespace orogen
