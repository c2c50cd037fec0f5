#include "graph/checked_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <streambuf>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace orogen {
namespace {

// Bytes still allowed before the injected ENOSPC; negative: no fault. Initialised from the environment.
std::atomic<std::int64_t>& fault_budget() {
  static std::atomic<std::int64_t> budget = [] {
    const char* env = std::getenv("OROGEN_TEST_ENOSPC_AFTER_BYTES");
    if (!env || !*env) return std::int64_t{-1};
    char* end = nullptr;
    const long long v = std::strtoll(env, &end, 10);
    return (end && *end == '\0' && v >= 0) ? static_cast<std::int64_t>(v) : std::int64_t{-1};
  }();
  return budget;
}

// How many of `size` bytes the injected fault lets through (all of them when no fault is set).
std::size_t allowed_by_fault(std::size_t size) {
  auto& budget = fault_budget();
  std::int64_t left = budget.load();
  while (left >= 0) {
    const auto take = static_cast<std::int64_t>(std::min<std::uint64_t>(size, static_cast<std::uint64_t>(left)));
    if (budget.compare_exchange_weak(left, left - take)) return static_cast<std::size_t>(take);
  }
  return size;
}

}  // namespace

void inject_write_failure_after(std::int64_t bytes) { fault_budget().store(bytes < 0 ? -1 : bytes); }

int sync_directory(const std::filesystem::path& dir) noexcept {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno;
  int err = 0;
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) err = errno;
  ::close(fd);
  return err;
}

CheckedFile::CheckedFile(const std::filesystem::path& path) : path_(path) {
  const std::string& s = path.native();
  if (s.find('\0') != std::string::npos) throw WriteError("cannot create '" + s + "': the name contains a NUL");
  do {
    fd_ = ::open(s.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  } while (fd_ < 0 && errno == EINTR);
  if (fd_ < 0) throw WriteError("cannot create '" + s + "': " + std::strerror(errno));
}

CheckedFile::~CheckedFile() {
  if (fd_ >= 0) ::close(fd_);
}

void CheckedFile::record_errno(const char* what, int err) noexcept {
  if (!error_.empty()) return;
  try {
    error_ = std::string(what) + " '" + path_.string() + "' failed: " + std::strerror(err);
    if (err == ENOSPC || err == EDQUOT) error_ += " (the disk or quota is full)";
  } catch (...) {}
}

void CheckedFile::fail(const std::string& why) {
  if (error_.empty()) error_ = "writing '" + path_.string() + "' failed: " + why;
}

bool CheckedFile::write_at(const char* data, std::size_t size, std::int64_t offset) noexcept {
  if (!error_.empty() || fd_ < 0) return false;
  while (size > 0) {
    std::size_t chunk = std::min<std::size_t>(size, std::size_t{1} << 30);
    chunk = allowed_by_fault(chunk);
    if (chunk == 0) {
      record_errno("writing", ENOSPC);
      return false;
    }
    const ssize_t n = ::pwrite(fd_, data, chunk, static_cast<off_t>(offset));
    if (n < 0) {
      if (errno == EINTR) continue;
      record_errno("writing", errno);
      return false;
    }
    if (n == 0) {
      record_errno("writing", EIO);
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
    offset += n;
    size_ = std::max(size_, offset);
  }
  return true;
}

bool CheckedFile::write(const void* data, std::size_t size) noexcept {
  const bool ok = write_at(static_cast<const char*>(data), size, position_);
  if (ok) position_ += static_cast<std::int64_t>(size);
  return ok;
}

bool CheckedFile::pwrite(const void* data, std::size_t size, std::int64_t offset) noexcept {
  return write_at(static_cast<const char*>(data), size, offset);
}

void CheckedFile::start_writeback(std::int64_t offset, std::int64_t bytes) noexcept {
#ifdef __linux__
  if (fd_ >= 0 && error_.empty() && bytes > 0)
    (void)::sync_file_range(fd_, static_cast<off64_t>(offset), static_cast<off64_t>(bytes), SYNC_FILE_RANGE_WRITE);
#else
  (void)offset, (void)bytes;
#endif
}

void CheckedFile::finish() {
  if (fd_ >= 0) {
    if (error_.empty() && ::fsync(fd_) != 0 && errno != EINVAL && errno != EROFS) record_errno("syncing", errno);
    if (::close(fd_) != 0 && errno != EINTR) record_errno("closing", errno);
    fd_ = -1;
  }
  if (!error_.empty()) throw WriteError(error_);
}

// ------------------------------------------------------------------------------------------------------------

struct CheckedOStream::Buffer : std::streambuf {
  explicit Buffer(const std::filesystem::path& path) : file(path), space(1 << 16) {
    setp(space.data(), space.data() + space.size());
  }
  bool drain() {
    const auto n = static_cast<std::size_t>(pptr() - pbase());
    const bool ok = !stopped && (n == 0 || file.write(pbase(), n));
    setp(space.data(), space.data() + space.size());
    return ok && polled();
  }
  // Runs the poll; false (and the exception kept) if it threw.
  bool polled() {
    if (stopped) return false;
    if (!poll) return true;
    try {
      poll();
      return true;
    } catch (...) {
      stopped = std::current_exception();
      return false;
    }
  }
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return drain() ? 0 : -1; }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n > static_cast<std::streamsize>(epptr() - pptr())) {
      if (!drain()) return 0;
      if (n >= static_cast<std::streamsize>(space.size())) {
        // A large block goes straight to the file, polled between buffer-sized pieces.
        for (std::streamsize done = 0; done < n;) {
          const auto piece = std::min<std::streamsize>(n - done, static_cast<std::streamsize>(space.size()));
          if (!file.write(s + done, static_cast<std::size_t>(piece)) || !polled()) return done;
          done += piece;
        }
        return n;
      }
    }
    std::memcpy(pptr(), s, static_cast<std::size_t>(n));
    pbump(static_cast<int>(n));
    return n;
  }
  // Seeking is needed by no writer we use; refuse it so a format that needs it fails loudly.
  CheckedFile file;
  std::vector<char> space;
  std::function<void()> poll;
  std::exception_ptr stopped;  // what the poll threw
};

CheckedOStream::CheckedOStream(const std::filesystem::path& path)
    : std::ostream(nullptr), buffer_(std::make_unique<Buffer>(path)) {
  rdbuf(buffer_.get());
}

CheckedOStream::~CheckedOStream() { rdbuf(nullptr); }

CheckedFile& CheckedOStream::file() { return buffer_->file; }

void CheckedOStream::set_poll(std::function<void()> poll) { buffer_->poll = std::move(poll); }

void CheckedOStream::rethrow_poll() const {
  if (buffer_->stopped) std::rethrow_exception(buffer_->stopped);
}

void CheckedOStream::finish() {
  flush();
  rethrow_poll();
  if (!buffer_->drain() || bad() || fail()) buffer_->file.fail("the stream reported an error");
  buffer_->file.finish();
}

void write_text_file(const std::filesystem::path& path, std::string_view text) {
  CheckedFile out(path);
  out.write(text.data(), text.size());
  out.finish();
}

}  // namespace orogen
