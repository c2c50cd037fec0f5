#pragma once
// The persistent result cache: one file per key, <dir>/<first 2 hex digits>/<32 hex digits>.orc.
//
// A file is a fixed header (magic, container and value format versions, the key, the payload length and an
// XXH3-64 checksum of the payload) followed by the serialized CachedResult. Files are written atomically, so
// a crash leaves either the old entry or none; a file that is truncated, corrupted, written by another
// format version or filed under the wrong key is rejected: deleted, and reported so the node is recomputed.
#include <filesystem>
#include <memory>
#include <string>

#include "evaluator/cache_key.h"
#include "evaluator/cached_result.h"

namespace orogen {

class DiskCache {
 public:
  explicit DiskCache(std::filesystem::path dir) : dir_(std::move(dir)) {}

  struct Loaded {
    std::shared_ptr<const CachedResult> result;  // null on a miss or a rejection
    bool rejected = false;                       // an entry existed but was not valid (and is now deleted)
    std::string reason;                          // why it was rejected
  };
  // Never throws for a bad entry: it is deleted and reported as rejected.
  Loaded load(const CacheKey& key) const;
  // Writes the entry atomically; throws std::exception on an I/O failure.
  void store(const CacheKey& key, const CachedResult& result) const;
  // Deletes the entry (e.g. when it does not fit the node it was looked up for).
  void remove(const CacheKey& key) const;

  std::filesystem::path path_of(const CacheKey& key) const;
  const std::filesystem::path& directory() const { return dir_; }

  static constexpr std::size_t kHeaderBytes = 48;

 private:
  std::filesystem::path dir_;
};

}  // namespace orogen
