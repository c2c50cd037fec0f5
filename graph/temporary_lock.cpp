#include "graph/temporary_lock.h"

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <random>
#include <stdexcept>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orogen {
namespace {

// 16 random hex digits, drawn again in a forked child (it must not share its parent's names).
std::string owner_id() {
  static std::mutex mutex;
  static pid_t drawn_for = 0;
  static std::string id;
  std::lock_guard lock(mutex);
  if (drawn_for != ::getpid()) {
    std::random_device device;
    const std::uint64_t r = (std::uint64_t{device()} << 32) ^ device();
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(r));
    id = text;
    drawn_for = ::getpid();
  }
  return id;
}

bool same_file(int fd, const std::filesystem::path& path) {
  struct stat by_fd {
  }, by_name{};
  return ::fstat(fd, &by_fd) == 0 && ::lstat(path.c_str(), &by_name) == 0 && by_fd.st_dev == by_name.st_dev &&
         by_fd.st_ino == by_name.st_ino;
}

// Length of "<hex>-<digits>" at the start of `rest`, 0 if it is not there.
std::size_t tag_length(std::string_view rest) {
  std::size_t i = 0;
  while (i < rest.size() && ((rest[i] >= '0' && rest[i] <= '9') || (rest[i] >= 'a' && rest[i] <= 'f'))) ++i;
  if (i == 0 || i >= rest.size() || rest[i] != '-') return 0;
  std::size_t j = i + 1;
  while (j < rest.size() && rest[j] >= '0' && rest[j] <= '9') ++j;
  return j == i + 1 ? 0 : j;
}

}  // namespace

TemporaryLock::TemporaryLock(const std::filesystem::path& dir) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path base = dir.empty() ? std::filesystem::path(".") : dir;
  // A sweep may take and remove a lock file between our creating and locking it: then try another name.
  for (int attempt = 0; attempt < 64; ++attempt) {
    tag_ = owner_id() + "-" + std::to_string(counter.fetch_add(1));
    path_ = base / (std::string(kTemporaryLockPrefix) + tag_);
    int fd;
    do {
      fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    } while (fd < 0 && errno == EINTR);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      throw std::runtime_error("cannot create the lock file '" + path_.string() + "': " + std::strerror(errno));
    }
    int locked;
    do {
      locked = ::flock(fd, LOCK_EX | LOCK_NB);
    } while (locked != 0 && errno == EINTR);
    // Without flock support nobody can take the lock from us either; the file alone then marks ownership.
    const bool held = locked == 0 || (errno != EWOULDBLOCK && errno != EAGAIN);
    if (held && same_file(fd, path_)) {
      fd_ = fd;
      return;
    }
    ::close(fd);  // a sweep holds it and removes it
  }
  throw std::runtime_error("cannot create a lock file in '" + base.string() + "': every name was taken");
}

TemporaryLock::~TemporaryLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // before releasing: nobody may find it unlocked while the name still exists
  ::close(fd_);
}

TemporaryKind temporary_kind(std::string_view filename, std::string* tag) {
  TemporaryKind kind = TemporaryKind::None;
  if (filename.substr(0, kTemporaryPrefix.size()) == kTemporaryPrefix)
    kind = TemporaryKind::Temporary;
  else if (filename.substr(0, kTemporaryLockPrefix.size()) == kTemporaryLockPrefix)
    kind = TemporaryKind::Lock;
  else
    return TemporaryKind::None;
  const std::string_view rest = filename.substr(kTemporaryPrefix.size());  // both prefixes have one length
  const std::size_t n = tag_length(rest);
  if (n == 0) return TemporaryKind::None;
  // A temporary may carry an extension; a lock file carries nothing after its tag.
  if (n < rest.size() && (kind == TemporaryKind::Lock || rest[n] != '.')) return TemporaryKind::None;
  if (tag) *tag = std::string(rest.substr(0, n));
  return kind;
}

bool claim_stale_tag(const std::filesystem::path& dir, const std::string& tag) {
  const std::filesystem::path lock =
      (dir.empty() ? std::filesystem::path(".") : dir) / (std::string(kTemporaryLockPrefix) + tag);
  int fd;
  do {
    fd = ::open(lock.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) return errno == ENOENT;  // no lock file: its owner finished or never locked (then it is gone)
  int locked;
  do {
    locked = ::flock(fd, LOCK_EX | LOCK_NB);
  } while (locked != 0 && errno == EINTR);
  const bool stale = locked == 0;
  if (stale && same_file(fd, lock)) ::unlink(lock.c_str());
  ::close(fd);
  return stale;
}

}  // namespace orogen
