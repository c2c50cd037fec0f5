#pragma once
// Atomic file replacement: a failed or cancelled write never leaves a half-written file and never destroys
// the previous one.
#include <filesystem>
#include <functional>
#include <string_view>

namespace orogen {

// Calls `write` with a temporary path beside `path` (same directory, same extension, so format detection
// by extension still works), then renames the temporary over `path`. If `write` throws, or leaves no file,
// the temporary is removed, `path` is untouched, and the exception propagates. Parent directories are
// created as needed.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write);

// Convenience: atomically replace `path` with `contents`.
void write_text_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace orogen
