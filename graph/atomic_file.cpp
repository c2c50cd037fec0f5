#include "graph/atomic_file.h"

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include "graph/checked_file.h"

namespace orogen {
namespace {

constexpr std::string_view kTemporaryPrefix = ".orogen-tmp-";

// The pid in a temporary's name, or 0.
long temporary_pid(std::string_view name) {
  if (name.substr(0, kTemporaryPrefix.size()) != kTemporaryPrefix) return 0;
  name.remove_prefix(kTemporaryPrefix.size());
  long pid = 0;
  const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), pid);
  if (ec != std::errc() || end == name.data() || end == name.data() + name.size() || *end != '-') return 0;
  return pid;
}

bool process_gone(long pid) { return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

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

}  // namespace

bool is_temporary_name(std::string_view filename) { return temporary_pid(filename) > 0; }

std::size_t remove_stale_temporaries(const std::filesystem::path& dir, int depth) {
  namespace fs = std::filesystem;
  std::size_t removed = 0;
  std::error_code ec;
  fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const auto& entry = *it;
    std::error_code ignored;
    const auto status = entry.symlink_status(ignored);
    const std::string name = entry.path().filename().string();
    if (fs::is_regular_file(status) && process_gone(temporary_pid(name))) {
      if (::unlink(entry.path().c_str()) == 0) ++removed;
    } else if (depth > 0 && fs::is_directory(status)) {
      removed += remove_stale_temporaries(entry.path(), depth - 1);
    }
  }
  return removed;
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  if (path.native().find('\0') != std::string::npos)
    throw std::runtime_error("cannot write '" + path.string() + "': the name contains a NUL character");
  if (path.filename().empty()) throw std::runtime_error("cannot write '" + path.string() + "': not a file name");
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  sweep_once(path.parent_path());
  std::string name(kTemporaryPrefix);
  name += std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  // Keep a plausible extension for writers that pick the format from it; a very long one is not a format.
  if (const auto ext = path.extension().string(); ext.size() <= 16) name += ext;
  const fs::path temporary = path.parent_path() / name;
  try {
    write(temporary);
    // Durable before it replaces the previous file: whatever wrote it, a crash after the rename must not
    // leave an empty or partial file in its place.
    const int fd = ::open(temporary.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT) throw std::runtime_error("nothing was written to " + path.string());
      throw std::runtime_error("cannot reopen '" + temporary.string() + "': " + std::strerror(errno));
    }
    const int sync_error = ::fsync(fd) == 0 ? 0 : errno;
    ::close(fd);
    if (sync_error != 0 && sync_error != EINVAL && sync_error != EROFS)
      throw std::runtime_error("cannot write '" + path.string() + "': " + std::strerror(sync_error));
    if (::rename(temporary.c_str(), path.c_str()) != 0)
      throw std::runtime_error("cannot replace '" + path.string() + "': " + std::strerror(errno));
  } catch (...) {
    ::unlink(temporary.c_str());  // only the file we created: unlink never removes a directory
    throw;
  }
  if (const int err = sync_directory(path.parent_path()); err != 0)
    throw std::runtime_error("cannot sync the directory of '" + path.string() + "': " + std::strerror(err));
}

void write_text_atomically(const std::filesystem::path& path, std::string_view contents) {
  write_file_atomically(path, [&](const std::filesystem::path& temporary) {
    CheckedFile out(temporary);
    out.write(contents.data(), contents.size());
    out.finish();
  });
}

}  // namespace orogen
