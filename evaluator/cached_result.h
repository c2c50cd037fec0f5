#pragma once
// What the cache stores for one node result: all its outputs, plus the files a writer node wrote.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "graph/port_value.h"

namespace orogen {

// A file a writer node wrote, as it was right after the write. A cached writer result is only trusted while
// every one of its files still has this size and modification time.
struct WrittenFile {
  std::filesystem::path path;
  std::uint64_t size = 0;
  std::int64_t mtime_ns = 0;  // file_time_type ticks as nanoseconds
  bool operator==(const WrittenFile&) const = default;

  // The record of `path` as it is now; throws std::filesystem::filesystem_error if it cannot be read.
  static WrittenFile stat(const std::filesystem::path& path);
  // Whether the file is still there unchanged.
  bool unchanged() const;
};

struct CachedResult {
  std::vector<PortValue> outputs;  // by output index
  std::vector<WrittenFile> files;  // writers only
  std::size_t value_bytes() const;
  // Whether every written file is still there unchanged (always true for non-writers).
  bool files_unchanged() const;
};

}  // namespace orogen
