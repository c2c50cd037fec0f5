#include "editor/model/recovery.h"

#include <algorithm>
#include <ctime>
#include <fstream>
#include <random>
#include <sstream>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "editor/model/document.h"
#include "graph/atomic_file.h"
#include "graph/graph_file.h"

namespace orogen::editor {

namespace {

constexpr const char* kFormat = "orogen-recovery";
constexpr const char* kSuffix = ".recovery.json";

std::string now_text() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
  return buf;
}

std::filesystem::path lock_for(const std::filesystem::path& file) {
  auto name = file.filename().string();
  name.resize(name.size() - std::string(kSuffix).size());
  return file.parent_path() / (name + ".lock");
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

RecoveryStore::RecoveryStore(std::filesystem::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  std::random_device rd;
  std::ostringstream name;
  name << "session-" << ::getpid() << "-" << std::hex << (static_cast<std::uint64_t>(rd()) << 32 | rd());
  file_ = dir_ / (name.str() + kSuffix);
  lock_file_ = dir_ / (name.str() + ".lock");
  lock_fd_ = ::open(lock_file_.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0600);
  if (lock_fd_ >= 0) ::flock(lock_fd_, LOCK_EX | LOCK_NB);
}

RecoveryStore::~RecoveryStore() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
  // Without a recovery file the lock file is litter; with one it marks the file as the user's to restore.
  std::error_code ec;
  if (!std::filesystem::exists(file_, ec)) std::filesystem::remove(lock_file_, ec);
}

void RecoveryStore::write(const Graph& graph, const std::filesystem::path& original) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = 1;
  j["original"] = original.string();
  j["saved_at"] = now_text();
  j["graph"] = nlohmann::json::parse(serialize_graph(graph));
  write_text_atomically(file_, j.dump(1) + "\n");
}

void RecoveryStore::discard() {
  std::error_code ec;
  std::filesystem::remove(file_, ec);
}

bool RecoveryStore::has_file() const {
  std::error_code ec;
  return std::filesystem::exists(file_, ec);
}

std::vector<RecoveryFile> RecoveryStore::orphans() const {
  std::vector<RecoveryFile> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    const auto path = entry.path();
    if (!ends_with(path.filename().string(), kSuffix) || path == file_) continue;
    // A session that still runs holds its lock.
    const int fd = ::open(lock_for(path).c_str(), O_RDWR | O_CLOEXEC);
    if (fd >= 0) {
      const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
      ::close(fd);
      if (!free) continue;
    }
    RecoveryFile rf;
    rf.file = path;
    rf.modified = entry.last_write_time(ec);
    try {
      std::ifstream in(path);
      const auto j = nlohmann::json::parse(in);
      if (j.value("format", "") != kFormat) continue;
      rf.original = j.value("original", "");
      rf.saved_at = j.value("saved_at", "");
    } catch (const std::exception&) {
      continue;  // half-written files cannot exist (atomic writes); anything else is not ours
    }
    out.push_back(std::move(rf));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.modified > b.modified; });
  return out;
}

Graph RecoveryStore::load(const RecoveryFile& file) {
  std::ifstream in(file.file);
  if (!in) throw DocumentError("cannot read " + file.file.string());
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw DocumentError("damaged recovery file " + file.file.string() + ": " + e.what());
  }
  LoadOptions options;
  options.allow_unconnected_inputs = true;
  auto result = parse_graph(j.at("graph").dump(), options);
  if (!result.ok()) throw DocumentError("the recovered graph is invalid:\n" + result.error_text());
  return std::move(*result.graph);
}

void RecoveryStore::remove(const RecoveryFile& file) {
  std::error_code ec;
  std::filesystem::remove(file.file, ec);
  std::filesystem::remove(lock_for(file.file), ec);
}

Autosaver::Autosaver(RecoveryStore& store, std::chrono::steady_clock::duration interval)
    : store_(store), interval_(interval) {}

bool Autosaver::tick(const Document& document, std::chrono::steady_clock::time_point now) {
  if (!document.dirty()) {
    if (written_) {
      store_.discard();
      written_ = false;
    }
    return false;
  }
  if (written_ && written_revision_ == document.revision()) return false;
  const bool wrote_before = last_write_ != std::chrono::steady_clock::time_point{};
  if (wrote_before && now - last_write_ < interval_) return false;
  flush(document);
  last_write_ = now;
  return error_.empty();
}

std::optional<std::chrono::steady_clock::time_point> Autosaver::next_due(const Document& document) const {
  if (!document.dirty()) return written_ ? std::optional(last_write_) : std::nullopt;
  if (written_ && written_revision_ == document.revision()) return std::nullopt;
  return last_write_ + interval_;  // never written: last_write_ is the epoch, so at once
}

void Autosaver::reset() {
  written_ = false;
  written_revision_ = 0;
  last_write_ = {};
}

void Autosaver::flush(const Document& document) {
  if (!document.dirty()) return;
  try {
    store_.write(document.graph(), document.path());
    written_ = true;
    written_revision_ = document.revision();
    error_.clear();
  } catch (const std::exception& e) {
    error_ = std::string("autosave failed: ") + e.what();
  }
}

}  // namespace orogen::editor
