#pragma once
// The persistent result cache: one file per key, <dir>/<first 2 hex digits>/<32 hex digits>.orc.
//
// A file is a fixed header (magic, container and value format versions, the key, the stored and the
// uncompressed payload lengths and an XXH3-64 checksum of the stored payload) followed by the serialized
// CachedResult compressed with zstd at a fast level. Files are written to a temporary name and renamed, so a
// concurrent process sees either a whole entry or none; they are not fsynced (a crash may leave an entry torn,
// which its checksum rejects). Anything at an entry's place that is not a valid entry (a directory, a link, an
// unreadable, truncated or corrupted file, another format version, the wrong key) is rejected: removed if
// possible, and reported so the node is recomputed.
// The cache never fails a build: every error of a lookup is a miss.
//
// Not every computed value is worth an entry (worth_storing): writing a value and reading it back costs CPU
// time in proportion to its size, and a value that a later run recomputes faster than that is left out.
//
// The directory is bounded: after a store that takes it past max_bytes, the least recently used entries
// (by modification time, which a hit refreshes) are removed until it is at 90% of the bound.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <memory>
#include <string>

#include "evaluator/cache_key.h"
#include "evaluator/cached_result.h"

namespace orogen {

class DiskCache {
 public:
  static constexpr std::uint64_t kDefaultMaxBytes = std::uint64_t(4) << 30;  // 4 GiB
  explicit DiskCache(std::filesystem::path dir, std::uint64_t max_bytes = kDefaultMaxBytes);

  struct Loaded {
    std::shared_ptr<const CachedResult> result;  // null on a miss or a rejection
    bool rejected = false;                       // an entry existed but was not valid (and is now deleted)
    std::string reason;                          // why it was rejected
  };
  // Never throws for a bad entry: it is deleted and reported as rejected.
  Loaded load(const CacheKey& key) const;
  // Writes the entry atomically; throws std::exception on an I/O failure.
  void store(const CacheKey& key, const CachedResult& result) const;
  // Whether a computed value deserves an entry. Values under kAlwaysStoredBytes always do (they cost next to
  // nothing either way); a larger one when a later run would spend longer recomputing it than writing and reading
  // the entry costs (kStoreAndLoadMsPerMiB). `recompute_ms` is the node's compute time plus that of the values
  // upstream that were not stored either, since a later run would recompute them with it. With the environment
  // variable OROGEN_CACHE_STORE=all, every value does.
  bool worth_storing(double recompute_ms, std::uint64_t bytes) const;
  static constexpr std::uint64_t kAlwaysStoredBytes = std::uint64_t(1) << 20;
  // CPU time to write an entry (serialize, compress, checksum, write: about 2 ms) and to read it back (about 2 ms),
  // per MiB of value: measured on the heightfields, images and meshes of graphs/seamscape.json at 2049^2.
  static constexpr double kStoreAndLoadMsPerMiB = 4.0;
  bool stores_everything() const { return store_everything_; }

  // Deletes the entry (e.g. when it does not fit the node it was looked up for).
  void remove(const CacheKey& key) const;

  std::filesystem::path path_of(const CacheKey& key) const;
  const std::filesystem::path& directory() const { return dir_; }

  static constexpr std::size_t kHeaderBytes = 56;

  // Removes least recently used entries until the directory holds at most `target` bytes of entries.
  // Returns how many were removed.
  std::size_t evict_to(std::uint64_t target) const;
  // Bytes of entries in the directory (a scan).
  std::uint64_t scan_bytes() const;
  std::uint64_t max_bytes() const { return max_bytes_; }

 private:
  std::filesystem::path dir_;
  std::uint64_t max_bytes_;
  bool store_everything_;                           // OROGEN_CACHE_STORE=all
  mutable std::atomic<std::int64_t> estimate_{-1};  // bytes in the directory as this process sees it; -1: unknown
  mutable std::mutex evict_mutex_;
};

}  // namespace orogen
