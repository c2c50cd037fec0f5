// HydraulicErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h).
//
// The whole-domain run's schedule (droplet_schedule.h) is a function of the whole domain: droplet rounds, blocks at
// least twice a droplet's reach across, four color phases per round, each block's droplets in index order. The
// tiles run that same schedule, a tile-graph round per phase:
//  - round 0: each tile sends its rectangle; every tile then knows which tile runs each block (the one holding the
//    block's center, the first in tile order on a shared border) and the region each tile keeps: its own samples
//    and the blocks it runs grown by the droplets' reach (DropletSchedule::margin), clipped to the domain;
//  - round 1: each tile sends the heights (and mask) of its own samples that lie in other tiles' regions;
//  - round 2 + p runs phase p: each tile runs its blocks of the phase on its region, then sends, for each such
//    block and each other tile whose region meets the block's reach, the samples of that overlap that changed in
//    the phase (a bit per sample, then the new values); each tile writes them into its region. The droplets of
//    two blocks of one phase touch disjoint samples, so every region holds the whole-domain run's heights after
//    every phase, and each block's droplets see exactly what they see in the whole-domain run: bit for bit;
//  - the next round sends each tile's per-block totals (added up in block order, as the whole-domain run adds
//    them) and the visit counts its blocks left on other tiles' samples; the last, each tile's most visits, whose
//    maximum scales the flow map.
// Every message goes to every rank (gather_by_tile); the solve forwards each part to its tile.
#include "nodes/erosion/particles_across_tiles.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/common/report_builder.h"
#include "nodes/erosion/droplet_schedule.h"
#include "graph/sample_rect.h"

namespace orogen::erosion {
namespace {

constexpr const char* kWhat = "hydraulic erosion across tiles";
constexpr int kMaxPhases = 1 << 20;

// Who runs which block and what each tile keeps, from every tile's rectangle: the same on every rank.
struct Plan {
  std::vector<SampleRect> rects;    // each tile's own samples
  std::vector<SampleRect> regions;  // each tile's samples and the reach of the blocks it runs
  std::vector<int> owner;           // per block: the tile that runs it
  std::vector<SampleRect> reach;    // per block: the samples its droplets may read or change
  // Per block: each other tile whose region meets the block's reach, and that overlap (what the block may change
  // there).
  struct Send {
    int target;
    SampleRect rect;
  };
  std::vector<std::vector<Send>> sends;
};

std::shared_ptr<const Plan> make_plan(const DropletSchedule& schedule, std::vector<SampleRect> rects) {
  auto plan = std::make_shared<Plan>();
  const SampleRect whole{{0, 0}, schedule.size() - 1};
  for (const SampleRect& r : rects)
    if (!r.within(whole))
      throw std::invalid_argument(std::string(kWhat) + ": a tile's rectangle does not fit the domain");
  plan->regions = rects;
  const int blocks = schedule.block_count();
  for (int b = 0; b < blocks; ++b) {
    const glm::ivec2 lo = schedule.block_lo(b), hi = schedule.block_hi(b), center = (lo + hi) / 2;
    const auto it = std::find_if(rects.begin(), rects.end(), [&](const SampleRect& r) { return r.contains(center); });
    if (it == rects.end()) throw std::invalid_argument(std::string(kWhat) + ": the tiles do not cover the domain");
    const int t = static_cast<int>(it - rects.begin());
    const SampleRect reach = overlap({lo - schedule.margin(), hi + schedule.margin()}, whole);
    plan->owner.push_back(t);
    plan->reach.push_back(reach);
    plan->regions[static_cast<std::size_t>(t)] = bounding(plan->regions[static_cast<std::size_t>(t)], reach);
  }
  plan->sends.resize(static_cast<std::size_t>(blocks));
  for (std::size_t b = 0; b < plan->sends.size(); ++b)
    for (std::size_t t = 0; t < rects.size(); ++t) {
      const SampleRect r = overlap(plan->reach[b], plan->regions[t]);
      if (static_cast<int>(t) != plan->owner[b] && !r.empty()) plan->sends[b].push_back({static_cast<int>(t), r});
    }
  plan->rects = std::move(rects);
  return plan;
}

// A part of a message: the samples of `rect` that one tile sends another, as 4-byte words per channel (floats, or
// visit counts), only those whose bit is set: target tile, the part's size in bytes, rectangle, channels, a bit per
// sample (row-major), then each channel's words of the set bits. The solve forwards parts to their target unread
// beyond their target and size.
constexpr std::size_t kPartHeader = 2 * sizeof(std::int32_t) + sizeof(std::uint64_t) + sizeof(SampleRect);
struct PartWriter {
  std::string& out;
  std::int32_t& parts;

  // Writes the part; `send(x, y)` says whether sample (x, y) goes, `word(c, x, y)` its word in channel c.
  template <class Send, class Word>
  void put(int target, const SampleRect& r, int channels, Send&& send, Word&& word) {
    if (r.empty()) return;
    const std::size_t at = out.size(), bits = (r.area() + 7) / 8;
    bytes::put(out, static_cast<std::int32_t>(target));
    bytes::put(out, std::uint64_t{0});  // the size, once known
    bytes::put(out, r);
    bytes::put(out, static_cast<std::int32_t>(channels));
    out.append(bits, '\0');
    std::size_t k = 0, set = 0;
    for (int y = r.lo.y; y <= r.hi.y; ++y)
      for (int x = r.lo.x; x <= r.hi.x; ++x, ++k)
        if (send(x, y)) {
          out[at + kPartHeader + k / 8] |= static_cast<char>(1u << (k % 8));
          ++set;
        }
    if (set == 0) {  // nothing to send
      out.resize(at);
      return;
    }
    for (int c = 0; c < channels; ++c) {
      k = 0;
      const char* mask = out.data() + at + kPartHeader;
      std::string words;
      words.reserve(set * 4);
      for (int y = r.lo.y; y <= r.hi.y; ++y)
        for (int x = r.lo.x; x <= r.hi.x; ++x, ++k)
          if (static_cast<unsigned char>(mask[k / 8]) >> (k % 8) & 1u) bytes::put(words, word(c, x, y));
      out += words;
    }
    const auto size = static_cast<std::uint64_t>(out.size() - at);
    std::memcpy(out.data() + at + sizeof(std::int32_t), &size, sizeof size);
    ++parts;
  }
};

struct PartHeader {
  int target = 0, channels = 0;
  SampleRect rect;
  std::string_view bits;   // a bit per sample
  std::size_t set = 0;     // bits set
  std::string_view words;  // channels x set words
};

// Takes one part from the front of `in`.
PartHeader take_part(std::string_view& in, const glm::ivec2 whole, std::size_t tiles) {
  PartHeader p;
  p.target = bytes::take<std::int32_t>(in, kWhat);
  const auto size = bytes::take<std::uint64_t>(in, kWhat);
  p.rect = bytes::take<SampleRect>(in, kWhat);
  p.channels = bytes::take<std::int32_t>(in, kWhat);
  if (p.target < 0 || static_cast<std::size_t>(p.target) >= tiles || p.channels < 1 || p.channels > 2 ||
      !p.rect.within({{0, 0}, whole - 1}))
    throw std::invalid_argument(std::string(kWhat) + ": a damaged part");
  const std::size_t bits = (p.rect.area() + 7) / 8;
  if (in.size() < bits) throw std::invalid_argument(std::string(kWhat) + ": truncated bytes");
  p.bits = in.substr(0, bits);
  in.remove_prefix(bits);
  for (const char c : p.bits) p.set += static_cast<std::size_t>(std::popcount(static_cast<unsigned char>(c)));
  const std::size_t words = p.set * static_cast<std::size_t>(p.channels) * 4;
  if (in.size() < words) throw std::invalid_argument(std::string(kWhat) + ": truncated bytes");
  p.words = in.substr(0, words);
  in.remove_prefix(words);
  if (size != kPartHeader + bits + words) throw std::invalid_argument(std::string(kWhat) + ": a damaged part");
  return p;
}

// fn(x, y, n) for every sample (x, y) the part sends, in order, n counting them (word_at(p, c, n) is its word in
// channel c).
template <class Fn>
void for_each_sent(const PartHeader& p, Fn&& fn) {
  std::size_t k = 0, n = 0;
  for (int y = p.rect.lo.y; y <= p.rect.hi.y; ++y)
    for (int x = p.rect.lo.x; x <= p.rect.hi.x; ++x, ++k)
      if (static_cast<unsigned char>(p.bits[k / 8]) >> (k % 8) & 1u) fn(x, y, n++);
}

template <class T>
T word_at(const PartHeader& p, int channel, std::size_t n) {
  T v;
  std::memcpy(&v, p.words.data() + (static_cast<std::size_t>(channel) * p.set + n) * 4, sizeof v);
  return v;
}

class ParticlesAcrossTiles;

class ParticleTile : public TileGraphTile {
 public:
  ParticleTile(const ParticlesAcrossTiles& algorithm, HeightfieldPtr in, HeightfieldPtr mask);
  std::string message(int round) override;
  void answer(int round, std::string_view bytes) override;
  std::vector<PortValue> outputs() override;

 private:
  std::size_t at(int x, int y) const {
    return static_cast<std::size_t>(y - region_.lo.y) * static_cast<std::size_t>(pitch_) +
           static_cast<std::size_t>(x - region_.lo.x);
  }
  void start_region();
  std::string run_phase(int phase);

  const ParticlesAcrossTiles& algorithm_;
  const DropletSchedule& schedule_;
  HeightfieldPtr in_, mask_;
  SampleRect own_;
  std::shared_ptr<const Plan> plan_;
  int me_ = -1;
  SampleRect region_;
  int pitch_ = 0;
  bool masked_ = false;  // a mask linked
  std::vector<float> z_, m_;
  std::vector<std::uint32_t> visits_;
  std::vector<DropletBlockStats> stats_;  // per block (those this tile runs)
  std::vector<int> mine_[4];              // this tile's blocks of each color
  ParticleStats totals_;
  std::uint32_t most_visits_ = 0;
};

class ParticlesAcrossTiles : public TileGraphAlgorithm {
 public:
  ParticlesAcrossTiles(const ParticleParams& p, const Domain& whole) : whole_(whole), schedule_(p, whole) {
    for (int c = 0; c < 4; ++c)
      if (!schedule_.color_blocks(c).empty()) colors_.push_back(c);
    // A round per phase: beyond a million rounds (dense droplets on a small grid) the all-gathers would cost more
    // than the droplets, and the count must fit the rounds' numbering; such runs stay on the whole domain.
    const double phases = static_cast<double>(schedule_.rounds()) * static_cast<double>(colors_.size());
    if (phases > kMaxPhases)
      throw NodeError("HydraulicErosion across tiles: over " + std::to_string(kMaxPhases) + " droplet phases");
    phases_ = static_cast<int>(phases);
  }

  // Rectangles, first values, a round per phase, the totals and visits, the most visits.
  int rounds() const override { return 2 + phases_ + 2; }
  int phases() const { return phases_; }
  // Droplet round and color of phase `phase`.
  std::pair<std::uint64_t, int> phase(int phase) const {
    const auto n = static_cast<int>(colors_.size());
    return {static_cast<std::uint64_t>(phase / n), colors_[static_cast<std::size_t>(phase % n)]};
  }

  const DropletSchedule& schedule() const { return schedule_; }
  const Domain& whole() const { return whole_; }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const HeightfieldPtr in = tile_heightfield(inputs, 0), mask = tile_heightfield(inputs, 1);
    if (!in) throw std::invalid_argument(std::string(kWhat) + " needs a heightfield input");
    if (mask && mask->domain.resolution != in->domain.resolution)
      throw std::invalid_argument(std::string(kWhat) + ": the mask must lie on the tile");
    require_finite_inputs("HydraulicErosion", {{"in", in.get()}, {"mask", mask.get()}});
    return std::make_unique<ParticleTile>(*this, in, mask);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    const std::size_t count = messages.size();
    std::vector<std::string> answers(count);
    if (round == 0) {
      std::string all;
      for (const std::string& m : messages) {
        if (m.size() != sizeof(SampleRect)) throw std::invalid_argument(std::string(kWhat) + ": a damaged tile");
        all += m;
      }
      std::fill(answers.begin(), answers.end(), all);
      return answers;
    }
    // The totals round: every block's totals in block order, added up as the whole-domain run adds them.
    std::string prefix;
    if (round == 2 + phases_) {
      std::vector<DropletBlockStats> blocks(static_cast<std::size_t>(schedule_.block_count()));
      std::vector<bool> seen(blocks.size(), false);
      std::vector<std::string_view> rest;
      for (const std::string& m : messages) {
        std::string_view in(m);
        const auto n = bytes::take<std::int32_t>(in, kWhat);
        for (std::int32_t i = 0; i < n; ++i) {
          const auto b = bytes::take<std::int32_t>(in, kWhat);
          if (b < 0 || static_cast<std::size_t>(b) >= blocks.size() || seen[static_cast<std::size_t>(b)])
            throw std::invalid_argument(std::string(kWhat) + ": a block's totals twice or out of range");
          seen[static_cast<std::size_t>(b)] = true;
          DropletBlockStats& s = blocks[static_cast<std::size_t>(b)];
          s.eroded = bytes::take<double>(in, kWhat), s.deposited = bytes::take<double>(in, kWhat);
          s.carried_off = bytes::take<double>(in, kWhat), s.steps = bytes::take<std::uint64_t>(in, kWhat);
        }
        rest.push_back(in);
      }
      if (std::find(seen.begin(), seen.end(), false) != seen.end())
        throw std::invalid_argument(std::string(kWhat) + ": a block's totals are missing");
      ParticleStats st;
      for (const auto& s : blocks) {
        st.eroded += s.eroded;
        st.deposited += s.deposited;
        st.carried_off += s.carried_off;
        st.steps += s.steps;
      }
      bytes::put(prefix, st.eroded), bytes::put(prefix, st.deposited), bytes::put(prefix, st.carried_off);
      bytes::put(prefix, st.steps);
      route(rest, prefix, answers);
      return answers;
    }
    if (round == 3 + phases_) {  // the most visits
      std::uint32_t most = 0;
      for (const std::string& m : messages) {
        std::string_view in(m);
        most = std::max(most, bytes::take<std::uint32_t>(in, kWhat));
        if (!in.empty()) throw std::invalid_argument(std::string(kWhat) + ": bytes left over");
      }
      for (auto& a : answers) bytes::put(a, most);
      return answers;
    }
    std::vector<std::string_view> views(messages.begin(), messages.end());
    route(views, prefix, answers);
    return answers;
  }

  // The plan of the tiling of `rects`, made once per tiling.
  std::shared_ptr<const Plan> plan(std::vector<SampleRect> rects) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!plan_ || plan_->rects != rects) plan_ = make_plan(schedule_, std::move(rects));
    return plan_;
  }

  // Round `round`'s droplets by block, binned once per round.
  std::shared_ptr<const DropletBins> bins(std::uint64_t round) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!bins_ || bins_round_ != round) {
      auto b = std::make_shared<DropletBins>();
      schedule_.bin(round, *b);
      bins_ = std::move(b), bins_round_ = round;
    }
    return bins_;
  }

 private:
  // Every message's parts (after `rest`'s prefix, read) forwarded to their target tile, in tile order; each answer
  // starts with `prefix` and the number of parts. Only a part's target and size are read here: its tile checks the
  // rest (take_part).
  void route(const std::vector<std::string_view>& messages, const std::string& prefix,
             std::vector<std::string>& answers) const {
    const std::size_t count = answers.size();
    std::vector<std::int32_t> parts(count, 0);
    for (std::string& a : answers) {
      a = prefix;
      bytes::put(a, std::int32_t{0});  // the number of parts, once known
    }
    for (std::string_view in : messages) {
      const auto n = bytes::take<std::int32_t>(in, kWhat);
      for (std::int32_t i = 0; i < n; ++i) {
        std::string_view header = in;
        const auto target = bytes::take<std::int32_t>(header, kWhat);
        const auto size = bytes::take<std::uint64_t>(header, kWhat);
        if (target < 0 || static_cast<std::size_t>(target) >= count || size < kPartHeader)
          throw std::invalid_argument(std::string(kWhat) + ": a damaged part");
        if (size > in.size()) throw std::invalid_argument(std::string(kWhat) + ": truncated bytes");
        answers[static_cast<std::size_t>(target)].append(in.data(), static_cast<std::size_t>(size));
        in.remove_prefix(static_cast<std::size_t>(size));
        ++parts[static_cast<std::size_t>(target)];
      }
      if (!in.empty()) throw std::invalid_argument(std::string(kWhat) + ": bytes left over");
    }
    for (std::size_t t = 0; t < count; ++t) std::memcpy(answers[t].data() + prefix.size(), &parts[t], sizeof parts[t]);
  }

  Domain whole_;
  DropletSchedule schedule_;
  std::vector<int> colors_;  // the colors with blocks, in phase order
  int phases_ = 0;
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const Plan> plan_;
  mutable std::shared_ptr<const DropletBins> bins_;
  mutable std::uint64_t bins_round_ = 0;
};

ParticleTile::ParticleTile(const ParticlesAcrossTiles& algorithm, HeightfieldPtr in, HeightfieldPtr mask)
    : algorithm_(algorithm),
      schedule_(algorithm.schedule()),
      in_(std::move(in)),
      mask_(std::move(mask)),
      own_(rect_of(in_->domain, algorithm.whole())) {}

std::string ParticleTile::message(int round) {
  std::string out;
  if (round == 0) {
    bytes::put(out, own_);
    return out;
  }
  const std::size_t tiles = plan_->rects.size();
  const int phases = algorithm_.phases();
  std::int32_t parts = 0;
  if (round == 1) {
    // Own heights (and mask) that other tiles' regions hold.
    bytes::put(out, parts);
    PartWriter w{out, parts};
    const int channels = masked_ ? 2 : 1;
    for (std::size_t t = 0; t < tiles; ++t)
      if (static_cast<int>(t) != me_)
        w.put(
            static_cast<int>(t), overlap(own_, plan_->regions[t]), channels, [](int, int) { return true; },
            [&](int c, int x, int y) { return c == 0 ? z_[at(x, y)] : m_[at(x, y)]; });
    std::memcpy(out.data(), &parts, sizeof parts);
    return out;
  }
  if (round < 2 + phases) return run_phase(round - 2);
  if (round == 2 + phases) {
    // This tile's blocks' totals, then the visits its blocks left on other tiles' samples.
    std::int32_t n = 0;
    for (std::size_t b = 0; b < plan_->owner.size(); ++b) n += plan_->owner[b] == me_;
    bytes::put(out, n);
    for (std::size_t b = 0; b < plan_->owner.size(); ++b)
      if (plan_->owner[b] == me_) {
        const DropletBlockStats& s = stats_[b];
        bytes::put(out, static_cast<std::int32_t>(b));
        bytes::put(out, s.eroded), bytes::put(out, s.deposited), bytes::put(out, s.carried_off);
        bytes::put(out, s.steps);
      }
    const std::size_t count_at = out.size();
    bytes::put(out, parts);
    PartWriter w{out, parts};
    for (std::size_t t = 0; t < tiles; ++t)
      if (static_cast<int>(t) != me_)
        w.put(
            static_cast<int>(t), overlap(region_, plan_->rects[t]), 1,
            [&](int x, int y) { return visits_[at(x, y)] != 0; }, [&](int, int x, int y) { return visits_[at(x, y)]; });
    std::memcpy(out.data() + count_at, &parts, sizeof parts);
    return out;
  }
  // The most visits of the tile's own samples (its blocks' and the others').
  std::uint32_t most = 0;
  for (int y = own_.lo.y; y <= own_.hi.y; ++y)
    for (int x = own_.lo.x; x <= own_.hi.x; ++x) most = std::max(most, visits_[at(x, y)]);
  bytes::put(out, most);
  return out;
}

std::string ParticleTile::run_phase(int phase) {
  const auto [round, color] = algorithm_.phase(phase);
  const std::vector<int>& blocks = mine_[color];
  // The heights each block's droplets may change in other tiles' regions, before they run: what differs after is
  // sent. (Blocks inside the tile's own samples, far from other regions, send nothing and copy nothing.)
  struct Outgoing {
    int target;
    SampleRect rect;
    std::vector<float> before;
  };
  std::vector<Outgoing> outgoing;
  for (const int b : blocks)
    for (const auto& [t, r] : plan_->sends[static_cast<std::size_t>(b)]) {
      Outgoing o{t, r, {}};
      o.before.reserve(r.area());
      for (int y = r.lo.y; y <= r.hi.y; ++y)
        o.before.insert(o.before.end(), z_.begin() + static_cast<std::ptrdiff_t>(at(r.lo.x, y)),
                        z_.begin() + static_cast<std::ptrdiff_t>(at(r.hi.x, y)) + 1);
      outgoing.push_back(std::move(o));
    }
  if (!blocks.empty()) {
    const auto bins = algorithm_.bins(round);
    DropletGrid grid;
    grid.z = z_.data();
    grid.visits = visits_.data();
    grid.mask = masked_ ? m_.data() : nullptr;
    grid.x0 = region_.lo.x, grid.y0 = region_.lo.y, grid.pitch = pitch_, grid.mask_pitch = pitch_;
    schedule_.run(grid, *bins, blocks, stats_.data(), nullptr);
  }
  std::string out;
  std::int32_t parts = 0;
  bytes::put(out, parts);
  PartWriter w{out, parts};
  for (const Outgoing& o : outgoing) {
    const SampleRect& r = o.rect;
    auto changed = [&](int x, int y) {
      const float a = o.before[static_cast<std::size_t>(y - r.lo.y) * r.size().x + (x - r.lo.x)], b = z_[at(x, y)];
      return std::memcmp(&a, &b, sizeof a) != 0;
    };
    w.put(o.target, r, 1, changed, [&](int, int x, int y) { return z_[at(x, y)]; });
  }
  std::memcpy(out.data(), &parts, sizeof parts);
  return out;
}

void ParticleTile::answer(int round, std::string_view in) {
  const int phases = algorithm_.phases();
  if (round == 0) {
    std::vector<SampleRect> rects;
    while (!in.empty()) rects.push_back(bytes::take<SampleRect>(in, kWhat));
    plan_ = algorithm_.plan(std::move(rects));
    const auto it = std::find(plan_->rects.begin(), plan_->rects.end(), own_);
    if (it == plan_->rects.end()) throw std::invalid_argument(std::string(kWhat) + ": the tile is not in the tiling");
    me_ = static_cast<int>(it - plan_->rects.begin());
    start_region();
    return;
  }
  if (round == 3 + phases) {
    most_visits_ = bytes::take<std::uint32_t>(in, kWhat);
    if (!in.empty()) throw std::invalid_argument(std::string(kWhat) + ": bytes left over");
    return;
  }
  if (round == 2 + phases) {
    totals_.eroded = bytes::take<double>(in, kWhat), totals_.deposited = bytes::take<double>(in, kWhat);
    totals_.carried_off = bytes::take<double>(in, kWhat), totals_.steps = bytes::take<std::uint64_t>(in, kWhat);
    totals_.droplets = schedule_.droplets();
  }
  const auto n = bytes::take<std::int32_t>(in, kWhat);
  const SampleRect& into = round == 2 + phases ? own_ : region_;
  for (std::int32_t i = 0; i < n; ++i) {
    const PartHeader p = take_part(in, schedule_.size(), plan_->rects.size());
    if (p.target != me_ || !p.rect.within(into) || (round != 1 && p.channels != 1) ||
        (round == 1 && p.channels != (masked_ ? 2 : 1)))
      throw std::invalid_argument(std::string(kWhat) + ": a part for another tile");
    if (round == 2 + phases)
      for_each_sent(p, [&](int x, int y, std::size_t k) { visits_[at(x, y)] += word_at<std::uint32_t>(p, 0, k); });
    else
      for_each_sent(p, [&](int x, int y, std::size_t k) {
        z_[at(x, y)] = word_at<float>(p, 0, k);
        if (round == 1 && masked_) m_[at(x, y)] = word_at<float>(p, 1, k);
      });
  }
  if (!in.empty()) throw std::invalid_argument(std::string(kWhat) + ": bytes left over");
}

void ParticleTile::start_region() {
  region_ = plan_->regions[static_cast<std::size_t>(me_)];
  pitch_ = DropletSchedule::pitch_for(region_.size().x);
  const std::size_t cells = static_cast<std::size_t>(region_.size().y) * static_cast<std::size_t>(pitch_);
  z_.assign(cells, 0.0f);
  visits_.assign(cells, 0u);
  if (mask_) m_.assign(cells, 0.0f);
  for (int j = 0; j < in_->height(); ++j)
    for (int i = 0; i < in_->width(); ++i) {
      const std::size_t q = at(own_.lo.x + i, own_.lo.y + j), k = in_->index(i, j);
      z_[q] = in_->data[k];
      if (mask_) m_[q] = mask_->data[k];
    }
  masked_ = mask_ != nullptr;
  mask_.reset();  // (kept in m_)
  stats_.assign(plan_->owner.size(), DropletBlockStats{});
  for (int c = 0; c < 4; ++c)
    for (const int b : schedule_.color_blocks(c))
      if (plan_->owner[static_cast<std::size_t>(b)] == me_) mine_[c].push_back(b);
}

std::vector<PortValue> ParticleTile::outputs() {
  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in_->domain);
  for (int j = 0; j < in_->height(); ++j)
    for (int i = 0; i < in_->width(); ++i) maps.out->at(i, j) = z_[at(own_.lo.x + i, own_.lo.y + j)];
  // Every map: the algorithm cannot know which outputs are linked (the whole-domain node skips the unlinked ones).
  maps.flow = std::make_shared<Heightfield>(in_->domain);
  const double lmax = std::log1p(static_cast<double>(most_visits_));
  if (lmax > 0)
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i)
        maps.flow->at(i, j) = droplet_flow(visits_[at(own_.lo.x + i, own_.lo.y + j)], lmax);
  fill_change_maps(*in_, maps, nullptr);
  ReportJson j;
  j["eroded"] = report_number(totals_.eroded);
  j["deposited"] = report_number(totals_.deposited);
  j["carried_off"] = report_number(totals_.carried_off);
  j["droplets"] = totals_.droplets;
  j["steps"] = totals_.steps;
  return {HeightfieldPtr(maps.out), HeightfieldPtr(maps.erosion), HeightfieldPtr(maps.deposition),
          HeightfieldPtr(maps.flow), ReportPtr(make_report(j))};
}

ParticleParams params_of(const ParamView& v) {
  ParticleParams p;
  p.droplets_per_km2 = v.get<double>("droplets_per_km2");
  p.step_length = v.get<double>("step_length");
  p.lifetime = v.get<double>("lifetime");
  p.radius = v.get<double>("radius");
  p.inertia = v.get<double>("inertia");
  p.capacity = v.get<double>("capacity");
  p.min_slope = v.get<double>("min_gradient");
  p.deposition = v.get<double>("deposition");
  p.erosion = v.get<double>("erosion");
  p.evaporation = v.get<double>("evaporation");
  p.gravity = v.get<double>("gravity");
  p.seed = v.get<std::uint64_t>("seed");
  return p;
}

// Every parameter value runs across the tiles; a run the whole-domain node would refuse (too many droplets or too
// much work) stays on the whole domain, whose node reports why (tile_graph_for).
const bool kParticlesRegistered = register_tile_graph("HydraulicErosion", [](const ParamView& v, const Domain& whole) {
  return particles_across_tiles(params_of(v), whole);
});

}  // namespace

std::unique_ptr<TileGraphAlgorithm> particles_across_tiles(const ParticleParams& p, const Domain& whole) {
  return std::make_unique<ParticlesAcrossTiles>(p, whole);
}

}  // namespace orogen::erosion
