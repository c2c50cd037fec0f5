#include "graph/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "graph/checked_file.h"
#include "graph/temporary_lock.h"

namespace orogen {
namespace {

// Each directory is swept once per process, the first time we write into it.
void sweep_once(const std::filesystem::path& dir) {
  static std::mutex mutex;
  static std::set<std::string> swept;
  {
    std::lock_guard lock(mutex);
    if (!swept.insert(dir.string()).second) return;
  }
  remove_stale_temporaries(dir);
}

// The extension a temporary keeps: the target's, in lower case (writers that pick the format from it then see
// ".glb" for "S.GLB"); none when very long, as that is no format.
std::string temporary_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (ext.size() > 16) return {};
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

void check_target(const std::filesystem::path& path) {
  if (path.native().find('\0') != std::string::npos)
    throw std::runtime_error("cannot write '" + path.string() + "': the name contains a NUL character");
  if (path.filename().empty()) throw std::runtime_error("cannot write '" + path.string() + "': not a file name");
}

// One file in flight: its lock (held until the temporary is renamed or removed) and its temporary.
struct Pending {
  std::filesystem::path target, temporary;
  std::unique_ptr<TemporaryLock> lock;
  bool renamed = false;
};

// Durable before it replaces the previous file: whatever wrote it, a crash after the rename must not leave an
// empty or partial file in its place.
void sync_temporary(const Pending& p) {
  const int fd = ::open(p.temporary.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) throw std::runtime_error("nothing was written to " + p.target.string());
    throw std::runtime_error("cannot reopen '" + p.temporary.string() + "': " + std::strerror(errno));
  }
  const int sync_error = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  if (sync_error != 0 && sync_error != EINVAL && sync_error != EROFS)
    throw std::runtime_error("cannot write '" + p.target.string() + "': " + std::strerror(sync_error));
}

}  // namespace

bool is_temporary_name(std::string_view filename) { return temporary_kind(filename) != TemporaryKind::None; }

std::size_t remove_stale_temporaries(const std::filesystem::path& dir, int depth) {
  namespace fs = std::filesystem;
  std::size_t removed = 0;
  std::error_code ec;
  const fs::path base = dir.empty() ? fs::path(".") : dir;
  fs::directory_iterator it(base, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const auto& entry = *it;
    std::error_code ignored;
    const auto status = entry.symlink_status(ignored);
    const std::string name = entry.path().filename().string();
    std::string tag;
    const TemporaryKind kind = temporary_kind(name, &tag);
    if (fs::is_regular_file(status) && kind == TemporaryKind::Temporary) {
      if (claim_stale_tag(base, tag) && ::unlink(entry.path().c_str()) == 0) ++removed;
    } else if (fs::is_directory(status) && kind == TemporaryKind::Temporary) {
      // A temporary directory (a tiled build's kept stage results, cli/tile_result_spill.h): removed whole.
      if (claim_stale_tag(base, tag) && fs::remove_all(entry.path(), ignored) > 0 && !ignored) ++removed;
    } else if (fs::is_regular_file(status) && kind == TemporaryKind::Lock) {
      claim_stale_tag(base, tag);  // a lock its owner left without a temporary: removed once nobody holds it
    } else if (depth > 0 && fs::is_directory(status)) {
      removed += remove_stale_temporaries(entry.path(), depth - 1);
    }
  }
  return removed;
}

void write_files_atomically(const std::vector<AtomicWrite>& files, Durability durability) {
  const bool synced = durability == Durability::Synced;
  namespace fs = std::filesystem;
  for (const auto& f : files) check_target(f.path);
  std::vector<Pending> pending;
  pending.reserve(files.size());
  try {
    for (const auto& f : files) {
      if (f.path.has_parent_path()) fs::create_directories(f.path.parent_path());
      sweep_once(f.path.parent_path());
      Pending p;
      p.target = f.path;
      p.lock = std::make_unique<TemporaryLock>(f.path.parent_path());
      const std::string name = std::string(kTemporaryPrefix) + p.lock->tag() + temporary_extension(f.path);
      p.temporary = f.path.parent_path() / name;
      pending.push_back(std::move(p));
      f.write(pending.back().temporary);
      if (synced) sync_temporary(pending.back());
    }
    for (auto& p : pending) {
      if (::rename(p.temporary.c_str(), p.target.c_str()) != 0)
        throw std::runtime_error("cannot replace '" + p.target.string() + "': " + std::strerror(errno));
      p.renamed = true;
      p.lock.reset();
    }
  } catch (...) {
    // Only the files we created: unlink never removes a directory. Each lock goes after its temporary.
    for (auto& p : pending)
      if (!p.renamed) {
        ::unlink(p.temporary.c_str());
        p.lock.reset();
      }
    throw;
  }
  if (!synced) return;
  std::set<fs::path> synced_dirs;
  for (const auto& p : pending)
    if (synced_dirs.insert(p.target.parent_path()).second)
      if (const int err = sync_directory(p.target.parent_path()); err != 0)
        throw std::runtime_error("cannot sync the directory of '" + p.target.string() + "': " + std::strerror(err));
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write,
                           Durability durability) {
  write_files_atomically({{path, write}}, durability);
}

void write_text_atomically(const std::filesystem::path& path, std::string_view contents) {
  write_file_atomically(path, [&](const std::filesystem::path& temporary) { write_text_file(temporary, contents); });
}

}  // namespace orogen
