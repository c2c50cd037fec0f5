#include "graph/rank_group.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace orogen {

namespace {

class SingleProcessGroup final : public RankGroup {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  int local_size() const override { return 1; }
  std::vector<std::string> all_gather(const std::string& mine) override { return {mine}; }
  void broadcast(std::string&, int) override {}
  std::vector<std::string> exchange(const std::vector<std::string>& outgoing) override {
    return {outgoing.empty() ? std::string() : outgoing[0]};
  }
  void barrier() override {}
  [[noreturn]] void abort(int code) override { std::exit(code); }
};

void put_u64(std::string& out, std::uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }

std::uint64_t get_u64(const std::string& in, std::size_t& at) {
  if (in.size() - at < sizeof(std::uint64_t)) throw std::runtime_error("gather_by_tile: truncated message");
  std::uint64_t v = 0;
  std::memcpy(&v, in.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

}  // namespace

std::unique_ptr<RankGroup> single_process_group() { return std::make_unique<SingleProcessGroup>(); }

std::vector<TilePart> gather_by_tile(RankGroup& group, const std::vector<TilePart>& mine) {
  std::string packed;
  put_u64(packed, mine.size());
  for (const auto& part : mine) {
    put_u64(packed, static_cast<std::uint64_t>(part.tile));
    put_u64(packed, part.bytes.size());
    packed += part.bytes;
  }
  std::vector<TilePart> all;
  for (const std::string& from : group.all_gather(packed)) {
    std::size_t at = 0;
    const std::uint64_t n = get_u64(from, at);
    for (std::uint64_t k = 0; k < n; ++k) {
      TilePart part;
      part.tile = static_cast<std::int64_t>(get_u64(from, at));
      const std::uint64_t len = get_u64(from, at);
      if (from.size() - at < len) throw std::runtime_error("gather_by_tile: truncated message");
      part.bytes = from.substr(at, len);
      at += len;
      all.push_back(std::move(part));
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const TilePart& a, const TilePart& b) { return a.tile < b.tile; });
  return all;
}

bool any_rank(RankGroup& group, bool mine) {
  const auto all = group.all_gather(std::string(1, mine ? '1' : '0'));
  return std::any_of(all.begin(), all.end(), [](const std::string& s) { return s == "1"; });
}

}  // namespace orogen
