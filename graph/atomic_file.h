#pragma once
// Atomic file replacement: a failed or cancelled write never leaves a half-written file and never destroys
// the previous one.
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

namespace orogen {

// Calls `write` with a temporary path beside `path` (same directory, same extension in lower case, so format
// detection by extension still works), makes the temporary durable (fsync), then renames it over `path` and
// syncs the directory. If `write` throws, or leaves no file, only the temporary is removed (never a
// directory), `path` is untouched, and the exception propagates. Parent directories are created as needed.
//
// Temporaries are named ".orogen-tmp-<owner>-<n><extension>", where <owner> is 16 hex digits drawn at random
// per process (unique across PID namespaces and hosts sharing a file system): short, so any legal file name
// can be written, and recognisable, so a later run removes those a killed process left behind. Each is owned
// by a lock: the file ".orogen-lck-<owner>-<n>" beside it, created and locked (flock) before the temporary
// exists and removed after the rename. remove_stale_temporaries deletes only temporaries whose lock no live
// process holds.
// Synced: the temporary and the directory are fsynced, so after a crash `path` holds the old or the new
// contents. Unsynced skips both: still never a half-written file seen by a running process, but a crash may
// leave the new file empty or partial; only for files whose reader verifies them (the result cache checksums
// its entries), where the two fsyncs cost more than the write.
enum class Durability { Synced, Unsynced };

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write,
                           Durability durability = Durability::Synced);

// One file of a set written together: its target and the function that writes its temporary.
struct AtomicWrite {
  std::filesystem::path path;
  std::function<void(const std::filesystem::path& temporary)> write;
};

// Writes every file of `files` to its temporary, syncs them all, and only then renames them over their targets
// in the given order (a file that names another, like an OBJ its material library, comes after it). A failure
// in any write, sync or rename removes the temporaries not yet renamed, so every target whose write failed
// keeps its previous contents; the exception propagates.
void write_files_atomically(const std::vector<AtomicWrite>& files, Durability durability = Durability::Synced);

// Convenience: atomically replace `path` with `contents`.
void write_text_atomically(const std::filesystem::path& path, std::string_view contents);

// True for a name write_file_atomically gives its temporaries or their lock files.
bool is_temporary_name(std::string_view filename);

// Removes temporaries of our naming in `dir` (and its subdirectories up to `depth` levels below, never
// following symbolic links) whose lock no live process holds, and lock files nobody holds. A temporary that is a
// directory (cli/tile_result_spill.h) is removed with everything in it. Safe while other
// processes, in any PID namespace or on any host sharing the file system, write into `dir`. Returns how many
// temporaries were removed; errors are ignored (a directory we cannot read holds nothing we wrote).
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, int depth = 0);

}  // namespace orogen
