#pragma once
// Output formatted into a 1 MiB block and written to a CheckedFile each time the block fills: one pass, large
// writes, every write checked (a full disk fails the writer), and `on_block` (a writer's cancellation poll)
// called after each block. Writers format straight into room(n) and advance(n), or put() bytes they have.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string_view>

#include "graph/checked_file.h"
#include "nodes/io/file_error.h"

namespace orogen {

class BlockWriter {
 public:
  static constexpr std::size_t kBlock = std::size_t(1) << 20;
  static constexpr std::size_t kMaxRoom = 4096;  // the most room() grants at once

  // Creates `path` (which must not exist); throws FileError.
  explicit BlockWriter(const std::filesystem::path& path, std::function<void()> on_block = {})
      : on_block_(std::move(on_block)), block_(new char[kBlock + kMaxRoom]) {
    try {
      file_ = std::make_unique<CheckedFile>(path);
    } catch (const WriteError& e) {
      throw FileError(e.what());
    }
  }

  // Room for up to kMaxRoom bytes at the end of the block; advance(n) after writing n <= kMaxRoom of them.
  char* room() {
    if (used_ >= kBlock) flush();
    return block_.get() + used_;
  }
  void advance(std::size_t n) { used_ += n; }

  void put(const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
      if (used_ >= kBlock) flush();
      const std::size_t k = std::min(n, kBlock - used_);
      std::memcpy(block_.get() + used_, p, k);
      used_ += k, p += k, n -= k;
    }
  }
  void put(std::string_view s) { put(s.data(), s.size()); }

  // Writes what the block holds, then polls.
  void flush() {
    if (used_ > 0 && !file_->write(block_.get(), used_)) throw FileError(file_->error());
    written_ += used_;
    used_ = 0;
    // Every 8 MiB the device starts on them, so that finish()'s sync has little left to wait for.
    if (written_ - synced_ >= 8 * kBlock) {
      file_->start_writeback(static_cast<std::int64_t>(synced_), static_cast<std::int64_t>(written_ - synced_));
      synced_ = written_;
    }
    if (on_block_) on_block_();
  }
  std::size_t bytes() const { return written_ + used_; }

  // Flushes, syncs and closes; throws FileError if any of it failed.
  void finish() {
    flush();
    try {
      file_->finish();
    } catch (const WriteError& e) {
      throw FileError(e.what());
    }
  }

 private:
  std::function<void()> on_block_;
  std::unique_ptr<char[]> block_;
  std::unique_ptr<CheckedFile> file_;
  std::size_t used_ = 0, written_ = 0, synced_ = 0;
};

}  // namespace orogen
