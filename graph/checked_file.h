#pragma once
// Writing files so that a full disk, a quota or an I/O error is never mistaken for success.
//
// CheckedFile is a file descriptor opened for exclusive creation (never following a symbolic link at the
// last component) whose every write is checked; finish() flushes it to stable storage (fsync) and checks
// close(). The first error is kept and reported with the file name and the system's reason. CheckedOStream
// is the same behind a std::ostream, for libraries that write to streams (OpenMesh, the points writer).
//
// For tests, writes can be made to fail part-way as on a full disk: inject_write_failure_after(n) (or the
// environment variable OROGEN_TEST_ENOSPC_AFTER_BYTES=n, read once) lets the next n bytes through, then
// every write fails with ENOSPC.
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace orogen {

struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CheckedFile {
 public:
  // Creates `path`, which must not exist (O_CREAT | O_EXCL | O_NOFOLLOW); throws WriteError.
  explicit CheckedFile(const std::filesystem::path& path);
  ~CheckedFile();  // closes without syncing if finish() was not called
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  // Appends at the current position / writes at `offset`. Return false (and keep the error) on failure.
  bool write(const void* data, std::size_t size) noexcept;
  bool pwrite(const void* data, std::size_t size, std::int64_t offset) noexcept;
  // Asks the kernel to start writing [offset, offset + bytes) to the device now, without waiting (Linux's
  // sync_file_range; nothing elsewhere): a writer producing a large file overlaps the device's work with its
  // own instead of leaving it all to finish()'s fsync. Failures are left to finish() to report.
  void start_writeback(std::int64_t offset, std::int64_t bytes) noexcept;
  std::int64_t position() const { return position_; }
  std::int64_t size() const { return size_; }

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  void fail(const std::string& why);  // records an error found by the caller (first one wins)

  // fsync and close; throws WriteError naming the file if any write, the sync or the close failed.
  void finish();

  const std::filesystem::path& path() const { return path_; }

 private:
  bool write_at(const char* data, std::size_t size, std::int64_t offset) noexcept;
  void record_errno(const char* what, int err) noexcept;

  std::filesystem::path path_;
  int fd_ = -1;
  std::int64_t position_ = 0, size_ = 0;
  std::string error_;
};

// A std::ostream into a CheckedFile. A failed write sets badbit; finish() flushes, syncs and throws the
// first error.
class CheckedOStream : public std::ostream {
 public:
  explicit CheckedOStream(const std::filesystem::path& path);
  ~CheckedOStream() override;
  void finish();  // rethrows what the poll threw, if anything, before any write error
  CheckedFile& file();

  // Called after each 64 KiB written: a writer's cancellation check, for libraries that write a whole file in
  // one call (OpenMesh). An exception it throws is kept and the stream fails, so the library stops writing;
  // rethrow_poll() (and finish()) rethrow it.
  void set_poll(std::function<void()> poll);
  void rethrow_poll() const;

 private:
  struct Buffer;
  std::unique_ptr<Buffer> buffer_;
};

// Creates `path` (which must not exist) holding `text`, every write checked and synced; throws WriteError.
void write_text_file(const std::filesystem::path& path, std::string_view text);

// Test hook: the next `bytes` bytes written through CheckedFile succeed, later writes fail with ENOSPC.
// A negative value turns the fault off.
void inject_write_failure_after(std::int64_t bytes);

// fsync of a directory (after a rename into it); errors other than EINVAL (unsupported) are returned.
int sync_directory(const std::filesystem::path& dir) noexcept;

}  // namespace orogen
