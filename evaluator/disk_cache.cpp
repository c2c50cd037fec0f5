#include "evaluator/disk_cache.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>
#include <zstd.h>

#include "evaluator/value_serialization.h"
#include "graph/atomic_file.h"
#include "graph/checked_file.h"

namespace orogen {
namespace {

constexpr char kMagic[8] = {'O', 'R', 'O', 'G', 'E', 'N', 'C', '1'};
constexpr std::uint32_t kContainerVersion = 2;  // 2: zstd-compressed payload, uncompressed length in the header
constexpr int kZstdLevel = 1;                   // fast: the cache is about time, not space
constexpr std::uint64_t kMaxPayloadBytes = std::uint64_t(1) << 40;

namespace fs = std::filesystem;

// Removes whatever is at `path` without following a link: a file, a link, or a directory tree.
void remove_entry(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::symlink_status(path, ec);
  if (ec) return;
  if (fs::is_directory(status))
    fs::remove_all(path, ec);
  else
    ::unlink(path.c_str());
}

// Reads the whole of an open file; false on a read error.
bool read_all(int fd, std::string& bytes, std::size_t size) {
  bytes.resize(size);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes.data() + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  char extra;
  return ::read(fd, &extra, 1) == 0;  // the file did not grow while we read it
}

// Entries below `dir` (the two-level layout), with their modification times and sizes.
struct EntryInfo {
  fs::path path;
  std::int64_t mtime_ns;
  std::uint64_t bytes;
};
std::vector<EntryInfo> list_entries(const fs::path& dir) {
  std::vector<EntryInfo> entries;
  std::error_code ec;
  for (fs::directory_iterator sub(dir, ec), end; !ec && sub != end; sub.increment(ec)) {
    std::error_code ec2;
    if (!fs::is_directory(sub->symlink_status(ec2))) continue;
    for (fs::directory_iterator it(sub->path(), ec2); !ec2 && it != end; it.increment(ec2)) {
      if (it->path().extension() != ".orc") continue;
      struct stat st;
      if (::lstat(it->path().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
      entries.push_back({it->path(), std::int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec,
                         static_cast<std::uint64_t>(st.st_size)});
    }
  }
  return entries;
}

// What a thread reuses from one store to the next: the serialized payload, the compressed bytes and zstd's
// context. Serializing and compressing into fresh memory cost more than the compression (page faults and
// zero-filling of tens of MB per entry); buffers above kKeptBufferBytes are freed after each store, so a rare
// huge entry does not hold its memory for the rest of the run.
constexpr std::size_t kKeptBufferBytes = std::size_t(64) << 20;
struct StoreBuffers {
  std::string payload;
  std::unique_ptr<char[]> packed;
  std::size_t packed_capacity = 0;
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> context{ZSTD_createCCtx(), &ZSTD_freeCCtx};
};
StoreBuffers& store_buffers() {
  thread_local StoreBuffers buffers;
  return buffers;
}

std::string encode_payload(const CachedResult& result, std::string reuse) {
  ByteWriter w(std::move(reuse));
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

bool store_everything_requested() {
  const char* value = std::getenv("OROGEN_CACHE_STORE");
  return value && std::string_view(value) == "all";
}

}  // namespace

DiskCache::DiskCache(std::filesystem::path dir, std::uint64_t max_bytes)
    : dir_(std::move(dir)), max_bytes_(max_bytes), store_everything_(store_everything_requested()) {
  remove_stale_temporaries(dir_, 1);  // left by killed processes
}

bool DiskCache::worth_storing(double recompute_ms, std::uint64_t bytes) const {
  if (store_everything_ || bytes < kAlwaysStoredBytes) return true;
  const double mib = static_cast<double>(bytes) / double(std::uint64_t(1) << 20);
  return recompute_ms > mib * kStoreAndLoadMsPerMiB;
}

std::filesystem::path DiskCache::path_of(const CacheKey& key) const {
  const auto hex = key.hex();
  return dir_ / hex.substr(0, 2) / (hex + ".orc");
}

void DiskCache::store(const CacheKey& key, const CachedResult& result) const {
  StoreBuffers& buffers = store_buffers();
  std::string payload = encode_payload(result, std::move(buffers.payload));
  const std::size_t bound = ZSTD_compressBound(payload.size());
  if (buffers.packed_capacity < bound) {
    buffers.packed.reset();  // first: the old buffer goes before the new one is faulted in
    buffers.packed = std::make_unique_for_overwrite<char[]>(bound);
    buffers.packed_capacity = bound;
  }
  if (!buffers.context) throw std::runtime_error("zstd: cannot create a compression context");
  const std::size_t packed =
      ZSTD_compressCCtx(buffers.context.get(), buffers.packed.get(), bound, payload.data(), payload.size(), kZstdLevel);
  if (ZSTD_isError(packed)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(packed));
  const std::string_view stored(buffers.packed.get(), packed);
  struct GiveBack {  // the buffers return to the thread (or are freed if huge) however the store ends
    StoreBuffers& buffers;
    std::string& payload;
    ~GiveBack() {
      if (payload.capacity() <= kKeptBufferBytes) buffers.payload = std::move(payload);
      if (buffers.packed_capacity > kKeptBufferBytes) buffers.packed.reset(), buffers.packed_capacity = 0;
    }
  } give_back{buffers, payload};
  ByteWriter header;
  header.raw(kMagic, sizeof kMagic);
  header.u32(kContainerVersion);
  header.u32(kValueFormatVersion);
  header.u64(key.high);
  header.u64(key.low);
  header.u64(stored.size());
  header.u64(payload.size());
  header.u64(XXH3_64bits(stored.data(), stored.size()));
  if (header.buffer().size() != kHeaderBytes) throw std::logic_error("disk cache header size");

  const fs::path path = path_of(key);
  // The subdirectory must be a real directory inside the cache: a link there could send the entry anywhere.
  const fs::path sub = path.parent_path();
  std::error_code ec;
  const auto status = fs::symlink_status(sub, ec);
  if (fs::exists(status) && !fs::is_directory(status)) remove_entry(sub);
  fs::create_directories(sub);
  if (fs::is_directory(fs::symlink_status(path, ec))) remove_entry(path);  // a rename cannot replace a directory
  // Unsynced: an entry a crash leaves torn fails its checksum and is recomputed; two fsyncs per entry cost more
  // than writing it.
  write_file_atomically(
      path,
      [&](const fs::path& temporary) {
        CheckedFile out(temporary);
        out.write(header.buffer().data(), header.buffer().size());
        out.write(stored.data(), stored.size());
        out.finish();
      },
      Durability::Unsynced);

  const auto bytes = static_cast<std::int64_t>(kHeaderBytes + stored.size());
  std::int64_t estimate = estimate_.load();
  if (estimate < 0) {
    estimate_.store(static_cast<std::int64_t>(scan_bytes()));
  } else {
    estimate_ += bytes;
  }
  if (static_cast<std::uint64_t>(estimate_.load()) > max_bytes_) evict_to(max_bytes_ / 10 * 9);
}

std::uint64_t DiskCache::scan_bytes() const {
  std::uint64_t total = 0;
  for (const auto& e : list_entries(dir_)) total += e.bytes;
  return total;
}

std::size_t DiskCache::evict_to(std::uint64_t target) const {
  std::lock_guard lock(evict_mutex_);
  auto entries = list_entries(dir_);
  std::uint64_t total = 0;
  for (const auto& e : entries) total += e.bytes;
  std::sort(entries.begin(), entries.end(), [](const EntryInfo& a, const EntryInfo& b) {
    return a.mtime_ns != b.mtime_ns ? a.mtime_ns < b.mtime_ns : a.path < b.path;
  });
  std::size_t removed = 0;
  for (const auto& e : entries) {
    if (total <= target) break;
    if (::unlink(e.path.c_str()) == 0) ++removed;
    total -= e.bytes;  // gone, whether we or another process removed it
  }
  estimate_.store(static_cast<std::int64_t>(total));
  return removed;
}

void DiskCache::remove(const CacheKey& key) const { remove_entry(path_of(key)); }

DiskCache::Loaded DiskCache::load(const CacheKey& key) const {
  Loaded loaded;
  const auto path = path_of(key);
  auto reject = [&](std::string why) {
    remove_entry(path);
    loaded.result = nullptr;
    loaded.rejected = true;
    loaded.reason = path.string() + ": " + std::move(why);
    return loaded;
  };
  // A link or a file where the subdirectory should be: never follow it out of the cache.
  struct stat st;
  if (::lstat(path.parent_path().c_str(), &st) != 0) return loaded;  // a miss
  if (!S_ISDIR(st.st_mode)) {
    remove_entry(path.parent_path());
    loaded.rejected = true;
    loaded.reason = path.parent_path().string() + ": not a directory";
    return loaded;
  }
  int fd = -1;
  do {
    fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    if (errno == ENOENT) return loaded;  // a miss
    if (errno == ELOOP) return reject("a symbolic link, not a cache entry");
    return reject(std::string("cannot open: ") + std::strerror(errno));
  }
  std::string bytes;
  std::string why;
  if (::fstat(fd, &st) != 0)
    why = std::string("cannot stat: ") + std::strerror(errno);
  else if (!S_ISREG(st.st_mode))
    why = S_ISDIR(st.st_mode) ? "a directory, not a cache entry" : "not a regular file";
  else if (static_cast<std::uint64_t>(st.st_size) < kHeaderBytes)
    why = "truncated header";
  else if (static_cast<std::uint64_t>(st.st_size) > kMaxPayloadBytes)
    why = "implausibly large";
  else if (!read_all(fd, bytes, static_cast<std::size_t>(st.st_size)))
    why = "read error or changed while read";
  else
    ::futimens(fd, nullptr);  // a use: least recently used entries are evicted first
  ::close(fd);
  if (!why.empty()) return reject(why);

  ByteReader header(std::string_view(bytes).substr(0, kHeaderBytes));
  char magic[sizeof kMagic];
  header.raw(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) return reject("not an Orogen cache file");
  if (header.u32() != kContainerVersion) return reject("other container format version");
  if (header.u32() != kValueFormatVersion) return reject("other value format version");
  CacheKey stored_key;
  stored_key.high = header.u64();
  stored_key.low = header.u64();
  if (!(stored_key == key)) return reject("filed under the wrong key");
  const std::uint64_t length = header.u64();
  const std::uint64_t raw_length = header.u64();
  const std::uint64_t checksum = header.u64();
  const std::string_view stored = std::string_view(bytes).substr(kHeaderBytes);
  if (stored.size() != length) return reject("payload length differs from the header (truncated?)");
  if (XXH3_64bits(stored.data(), stored.size()) != checksum) return reject("checksum mismatch");
  if (raw_length > kMaxPayloadBytes || ZSTD_getFrameContentSize(stored.data(), stored.size()) != raw_length)
    return reject("compressed length differs from the header");
  try {
    std::string payload(static_cast<std::size_t>(raw_length), '\0');
    const std::size_t n = ZSTD_decompress(payload.data(), payload.size(), stored.data(), stored.size());
    if (ZSTD_isError(n) || n != raw_length) return reject("undecompressable payload");
    loaded.result = decode_payload(payload);
  } catch (const std::exception& e) {
    return reject(std::string("undecodable payload: ") + e.what());
  }
  return loaded;
}

}  // namespace orogen
