#pragma once
// The in-memory result cache: an LRU bounded in bytes, safe to use from several threads.
#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "evaluator/cache_key.h"
#include "evaluator/cached_result.h"

namespace orogen {

class MemoryCache {
 public:
  explicit MemoryCache(std::size_t capacity_bytes) : capacity_(capacity_bytes) {}

  // The entry for `key` (marked most recently used), or nullptr.
  std::shared_ptr<const CachedResult> find(const CacheKey& key);
  // Stores `result` under `key`, replacing an older entry, then evicts least recently used entries until the
  // total fits the capacity. A result larger than the whole capacity is not stored; returns whether it was.
  bool insert(const CacheKey& key, std::shared_ptr<const CachedResult> result, std::size_t bytes);
  void erase(const CacheKey& key);
  void clear();

  std::size_t entries() const;
  std::size_t bytes() const;
  std::size_t capacity() const { return capacity_; }
  std::size_t evictions() const;

 private:
  struct Entry {
    CacheKey key;
    std::shared_ptr<const CachedResult> result;
    std::size_t bytes = 0;
  };
  using List = std::list<Entry>;  // front: most recently used
  void erase_locked(List::iterator it);

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  List lru_;
  std::unordered_map<CacheKey, List::iterator, CacheKeyHash> index_;
  std::size_t bytes_ = 0;
  std::size_t evictions_ = 0;
};

}  // namespace orogen
