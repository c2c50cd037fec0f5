#pragma once
// Atomic file replacement: a failed or cancelled write never leaves a half-written file and never destroys
// the previous one.
#include <filesystem>
#include <functional>
#include <string_view>

namespace orogen {

// Calls `write` with a temporary path beside `path` (same directory, same extension, so format detection
// by extension still works), makes the temporary durable (fsync), then renames it over `path` and syncs the
// directory. If `write` throws, or leaves no file, only the temporary is removed (never a directory), `path`
// is untouched, and the exception propagates. Parent directories are created as needed.
//
// Temporaries are named ".orogen-tmp-<pid>-<n><extension>": short, so any legal file name can be written,
// and recognisable, so a later run removes those a killed process left behind (remove_stale_temporaries).
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write);

// Convenience: atomically replace `path` with `contents`.
void write_text_atomically(const std::filesystem::path& path, std::string_view contents);

// True for a name write_file_atomically gives its temporaries.
bool is_temporary_name(std::string_view filename);

// Removes temporaries of our naming in `dir` (and its subdirectories up to `depth` levels below, never
// following symbolic links) whose creating process no longer runs. Returns how many were removed; errors
// are ignored (a directory we cannot read holds nothing we wrote).
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, int depth = 0);

}  // namespace orogen
