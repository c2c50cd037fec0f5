#include "evaluator/memory_cache.h"

namespace orogen {

std::shared_ptr<const CachedResult> MemoryCache::find(const CacheKey& key) {
  std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) return nullptr;
  lru_.splice(lru_.begin(), lru_, it->second);
  return it->second->result;
}

bool MemoryCache::insert(const CacheKey& key, std::shared_ptr<const CachedResult> result, std::size_t bytes) {
  std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) erase_locked(it->second);
  if (bytes > capacity_) return false;
  lru_.push_front(Entry{key, std::move(result), bytes});
  index_[key] = lru_.begin();
  bytes_ += bytes;
  while (bytes_ > capacity_) {
    erase_locked(std::prev(lru_.end()));
    ++evictions_;
  }
  return true;
}

void MemoryCache::erase(const CacheKey& key) {
  std::lock_guard lock(mutex_);
  if (const auto it = index_.find(key); it != index_.end()) erase_locked(it->second);
}

void MemoryCache::erase_locked(List::iterator it) {
  bytes_ -= it->bytes;
  index_.erase(it->key);
  lru_.erase(it);
}

void MemoryCache::clear() {
  std::lock_guard lock(mutex_);
  lru_.clear();
  index_.clear();
  bytes_ = 0;
}

std::size_t MemoryCache::entries() const {
  std::lock_guard lock(mutex_);
  return lru_.size();
}
std::size_t MemoryCache::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}
std::size_t MemoryCache::evictions() const {
  std::lock_guard lock(mutex_);
  return evictions_;
}

}  // namespace orogen
