#pragma once
// The lock that owns a temporary file of write_file_atomically, so that a start-up sweep removes only the
// temporaries of processes that are gone, whatever PID namespace or host they ran in.
//
// A temporary ".orogen-tmp-<tag><ext>" is owned by the lock file ".orogen-lck-<tag>" beside it, where <tag> is
// "<owner>-<n>": 16 random hex digits per process and a counter. The writer creates the lock file, takes an
// exclusive flock on it and checks that the name still leads to the file it locked, all before the temporary
// exists; it removes the lock file only after the temporary is renamed or removed. The kernel (or, on NFS,
// the server) releases the lock when the process dies, however it dies. A temporary is stale when its lock
// file is missing or can be locked by someone else.
#include <filesystem>
#include <string>
#include <string_view>

namespace orogen {

class TemporaryLock {
 public:
  // Creates and locks a fresh lock file in `dir` (which must exist). Throws std::runtime_error.
  explicit TemporaryLock(const std::filesystem::path& dir);
  ~TemporaryLock();  // removes the lock file, then releases the lock
  TemporaryLock(const TemporaryLock&) = delete;
  TemporaryLock& operator=(const TemporaryLock&) = delete;

  // "<owner>-<n>": the part of the temporary's name this lock owns.
  const std::string& tag() const { return tag_; }

 private:
  std::filesystem::path path_;
  std::string tag_;
  int fd_ = -1;
};

inline constexpr std::string_view kTemporaryPrefix = ".orogen-tmp-";
inline constexpr std::string_view kTemporaryLockPrefix = ".orogen-lck-";

enum class TemporaryKind { None, Temporary, Lock };

// What a file name is to us: a temporary (".orogen-tmp-<tag>" plus an optional extension), a lock
// (".orogen-lck-<tag>") or neither; `tag` receives the tag. Older names ("<pid>-<n>") are tags too.
TemporaryKind temporary_kind(std::string_view filename, std::string* tag = nullptr);

// True when no live process holds the lock of `tag` in `dir`: the lock file is missing, or we could lock it
// (then it is removed). False while its owner runs, and whenever we cannot tell (an unreadable lock, a file
// system without flock): a temporary is never removed on a guess.
bool claim_stale_tag(const std::filesystem::path& dir, const std::string& tag);

}  // namespace orogen
