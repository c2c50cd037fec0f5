#include "evaluator/cached_result.h"

#include <chrono>
#include <system_error>

namespace orogen {

WrittenFile WrittenFile::stat(const std::filesystem::path& path) {
  WrittenFile f;
  f.path = path;
  f.size = std::filesystem::file_size(path);
  f.mtime_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::filesystem::last_write_time(path).time_since_epoch())
          .count();
  return f;
}

bool WrittenFile::unchanged() const {
  std::error_code ec;
  const auto size_now = std::filesystem::file_size(path, ec);
  if (ec || size_now != size) return false;
  const auto time_now = std::filesystem::last_write_time(path, ec);
  if (ec) return false;
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time_now.time_since_epoch()).count() == mtime_ns;
}

std::size_t CachedResult::value_bytes() const {
  std::size_t bytes = 0;
  for (const auto& v : outputs) bytes += byte_size(v);
  return bytes;
}

bool CachedResult::files_unchanged() const {
  for (const auto& f : files)
    if (!f.unchanged()) return false;
  return true;
}

}  // namespace orogen
