#pragma once
// Crash recovery. While a document has unsaved changes, the Autosaver periodically writes it to this
// session's recovery file; a clean exit or a save removes it. A recovery file whose session is no longer
// running is therefore what a crash left behind, and the next start offers to restore it.
//
// Each session holds an flock on a lock file beside its recovery file; the kernel drops the lock when the
// process dies, however it dies, so "no longer running" needs no pid guessing.
#include <chrono>
#include <optional>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "graph/graph.h"

namespace orogen::editor {

class Document;

struct RecoveryFile {
  std::filesystem::path file;      // the recovery file
  std::filesystem::path original;  // the file the document was opened from or saved to; empty if untitled
  std::string saved_at;            // local time of the last autosave, "YYYY-MM-DD HH:MM:SS"
  std::filesystem::file_time_type modified;
};

class RecoveryStore {
 public:
  // Recovery files live in `dir` (default_state_dir() / "recovery" in the app).
  explicit RecoveryStore(std::filesystem::path dir);
  ~RecoveryStore();  // releases the session lock but keeps the file: only discard() removes it
  RecoveryStore(const RecoveryStore&) = delete;
  RecoveryStore& operator=(const RecoveryStore&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  const std::filesystem::path& session_file() const { return file_; }

  // Atomically replaces this session's recovery file. Throws std::runtime_error if it cannot be written.
  void write(const Graph& graph, const std::filesystem::path& original);
  // Removes this session's recovery file (clean exit, successful save).
  void discard();
  bool has_file() const;

  // Recovery files of sessions that are not running any more, newest first.
  std::vector<RecoveryFile> orphans() const;
  // The graph in a recovery file; throws DocumentError if it cannot be read.
  static Graph load(const RecoveryFile& file);
  // Removes a recovery file and its lock (after restoring it or declining).
  static void remove(const RecoveryFile& file);

 private:
  std::filesystem::path dir_, file_, lock_file_;
  int lock_fd_ = -1;
};

// Decides when to write the recovery file: when the document has changes not yet written there and at
// least `interval` has passed since the last write; removes the file once the document is saved.
class Autosaver {
 public:
  explicit Autosaver(RecoveryStore& store, std::chrono::steady_clock::duration interval = std::chrono::seconds(20));
  // Call regularly (every frame). Returns true if it wrote the recovery file.
  bool tick(const Document& document, std::chrono::steady_clock::time_point now);
  // When tick() next has something to do for `document` (write or remove the recovery file), or nothing if
  // it has none: the main loop sleeps until then.
  std::optional<std::chrono::steady_clock::time_point> next_due(const Document& document) const;
  // Writes now if there is anything unsaved (before a risky operation, or on a signal).
  void flush(const Document& document);
  // Another document replaced the previous one: forget what was written for that one.
  void reset();
  const std::string& last_error() const { return error_; }

 private:
  RecoveryStore& store_;
  std::chrono::steady_clock::duration interval_;
  std::chrono::steady_clock::time_point last_write_{};
  std::uint64_t written_revision_ = 0;
  bool written_ = false;
  std::string error_;
};

}  // namespace orogen::editor
