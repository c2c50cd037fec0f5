#pragma once
// The results of a rank's tile-graph stages (cli/tile_graph_stages.h), kept on disk from the stage that computes
// them to the evaluations that use them: later stages' inputs, then the tile's own evaluation. A rank then holds in
// memory one stage's round state and one tile's results at a time, never every tile's results of every stage (at
// 32768^2 on 8 ranks those would be tens of bytes a sample, more than a rank's share of the machine).
//
// The files live in one directory inside the build's output folder (nothing is written outside it), named like
// the temporaries of graph/atomic_file.h (".orogen-tmp-<tag>.stages") and owned by their lock: removed when the
// build ends, however it ends, and by the next build's sweep (remove_stale_temporaries) if the process was killed.
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "evaluator/cached_result.h"
#include "graph/temporary_lock.h"

namespace orogen::cli {

class TileResultSpill {
 public:
  // Creates the directory in `folder` (created if missing). Throws std::runtime_error.
  explicit TileResultSpill(const std::filesystem::path& folder);
  ~TileResultSpill();  // removes the directory and everything in it
  TileResultSpill(const TileResultSpill&) = delete;
  TileResultSpill& operator=(const TileResultSpill&) = delete;

  // Writes the result of node `node` on this rank's tile `tile` (its index among the rank's tiles). Throws
  // std::runtime_error naming the file and the reason (a full disk).
  void put(std::size_t tile, const std::string& node, const CachedResult& result);
  // The result put for (tile, node), read back. Throws std::runtime_error if there is none or it cannot be read.
  std::shared_ptr<const CachedResult> get(std::size_t tile, const std::string& node) const;
  // Every result of `tile`, by node id, read back and their files removed (the tile's evaluation is their last use).
  std::map<std::string, std::shared_ptr<const CachedResult>> take(std::size_t tile);
  // The nodes with a result for `tile`.
  std::set<std::string> nodes(std::size_t tile) const;
  // Bytes written so far, for the stages' report.
  std::size_t bytes_written() const { return written_; }
  const std::filesystem::path& directory() const { return directory_; }

 private:
  std::filesystem::path file(std::size_t tile, const std::string& node) const;

  std::unique_ptr<TemporaryLock> lock_;
  std::filesystem::path directory_;
  std::map<std::size_t, std::set<std::string>> nodes_;
  std::size_t written_ = 0;
};

}  // namespace orogen::cli
