// StreamPower across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): the whole-domain run with
// Depressions::PriorityFlood (stream_power.cpp), step by step, each tile holding only its own samples. A step is the
// whole-domain step's stages, each completed across the tiles in rounds tagged with their phase:
//
//  - uplift, on the tile alone;
//  - halo: the tile's ring of heights (doubles) from the tiles around it (nodes/hydrology/tile_ring.h), before each
//    explicit diffusion sub-step (a sub-step reads the four neighbours) and once after the last, for the routing;
//  - pits: whether any tile has a cell other than the domain's border with no strictly lower 8-neighbour in float.
//    If none, the Priority-Flood+epsilon fill leaves the float surface as it is (every cell already has a lower
//    neighbour, so the epsilon surface is the surface itself), and the fill's rounds are skipped;
//  - basins and terminals (only with pits): the D8 paths joined through perimeter links (nodes/hydrology/tile_basins.h)
//    say where each cell's path ends, and the pits at those ends say which cells drain to a pit; only those can change
//    in the fill (nodes/hydrology/pit_basin_fill.h);
//  - region: each tile's pit-basin cells with the cells around them, filled in one piece by the solve when every
//    tile's are few, bit for bit the whole-domain fill there; else only a flag, and
//  - spill and epsilon: the fill across tiles (nodes/hydrology/tile_fill.h) with the cells outside the pit basins
//    drained, the whole-domain Priority-Flood+epsilon bit for bit, then the ring of the filled surface so the D8
//    receivers of the tile's perimeter cells see across its border. Raised cells count as deposition, as on the whole
//    domain;
//  - accumulate: D8 cell counts through perimeter links (nodes/hydrology/tile_accumulation.h), whole numbers, so the
//    area (count x cell area) is the whole-domain run's exactly;
//  - incise: the implicit incision goes from the outlets upstream, each cell from its receiver's new height. A tile
//    computes every cell whose receiver it holds, walking up from the cells already done; a chain that leaves a tile
//    leaves it through a sample it shares with the tile holding the receiver, so each round every tile sends the
//    shared samples it finished and takes those others finished, until a round sends nothing. Every cell is computed
//    by the same function of the same doubles as on the whole domain.
//
// After the last step, the float fill of the result (pits, basins, the fill) and the largest drainage area over all
// tiles (for the flow map). Base level is the domain's border and, as on the whole domain, the cells under sea level
// after each step's uplift: they take no diffusion, have no receiver, and are drained cells of the fill. Which pits
// end the paths of the tile's cells: its own, and those other tiles name for the paths from their perimeters (a path
// that enters a tile does so through its perimeter), one round.
#include "nodes/erosion/stream_power_across_tiles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/erosion_common.h"
#include "nodes/erosion/stream_power_kernel.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/pit_basin_fill.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_basins.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_ring.h"

namespace orogen::erosion {
namespace {

using hydrology::FlowGrid;
using hydrology::TileRect;

enum class Phase : std::uint8_t {
  Halo,
  Pits,
  Basins,
  Terminals,
  Region,
  Spill,
  Epsilon,
  Ring,
  Accumulate,
  Incise,
  Maximum,
  Done
};

// A tile fills its pit basins by sending them to the solve when they hold at most 1/kRegionShare of its cells (or
// kRegionCells), and every tile's do; else the fill of the pit basins runs across the tiles.
constexpr std::size_t kRegionShare = 16, kRegionCells = 1024;
std::size_t default_region_limit(std::size_t tile_cells) { return std::max(kRegionCells, tile_cells / kRegionShare); }

constexpr const char* kWhat = "stream power across tiles";

Phase take_phase(std::string_view& bytes) { return hydrology::take_phase<Phase>(bytes, kWhat, kWhat); }

// Heights at domain samples (row-major indices), as the fill's and the incision's rounds carry them.
template <class T>
struct SampleHeights {
  std::vector<std::int64_t> samples;
  std::vector<T> heights;

  void push(std::int64_t sample, T height) { samples.push_back(sample), heights.push_back(height); }
  void put(std::string& out) const { bytes::put_vector(out, samples), bytes::put_vector(out, heights); }
  static SampleHeights take(std::string_view& in) {
    SampleHeights h{bytes::take_vector<std::int64_t>(in, kWhat), bytes::take_vector<T>(in, kWhat)};
    if (h.samples.size() != h.heights.size())
      throw std::invalid_argument("stream power across tiles: truncated heights");
    return h;
  }
};

bool holds(const TileRect& r, int x, int y) {
  return x >= r.first.x && y >= r.first.y && x < r.first.x + r.size.x && y < r.first.y + r.size.y;
}

class StreamPowerTile : public TileGraphTile {
 public:
  StreamPowerTile(const Heightfield& in, const Heightfield* mask, const Heightfield* uplift, const StreamPowerParams& p,
                  const StreamPowerSchedule& schedule, std::shared_ptr<const StreamPowerIncision> incision,
                  const Domain& whole, std::optional<std::size_t> region_limit)
      : p_(p),
        schedule_(schedule),
        incision_(std::move(incision)),
        domain_(in.domain),
        whole_(whole.resolution),
        whole_spacing_(whole.spacing),
        grid_(FlowGrid::of(whole)),
        rect_{in.domain.first, in.domain.resolution},
        ringed_(hydrology::ringed_rect(rect_, whole_)),
        n_(in.data.size()),
        region_limit_(region_limit.value_or(default_region_limit(n_))) {
    z_.assign(in.data.begin(), in.data.end());
    ero_.assign(n_, 0.0);
    dep_.assign(n_, 0.0);
    kfac_.resize(n_);
    ufac_.resize(n_);
    fixed_.resize(n_);
    outlet_.resize(n_);
    for (int j = 0; j < rect_.size.y; ++j)
      for (int i = 0; i < rect_.size.x; ++i) {
        const std::size_t k = in.index(i, j);
        const int gi = rect_.first.x + i, gj = rect_.first.y + j;
        fixed_[k] = gi == 0 || gj == 0 || gi == whole_.x - 1 || gj == whole_.y - 1;
        kfac_[k] = mask_at(mask, k);
        ufac_[k] = fixed_[k] ? 0.0 : p.uplift * (uplift ? std::max(0.0f, uplift->data[k]) : 1.0f);
      }
    start_step();
  }

  std::string message(int) override {
    std::string out;
    switch (phase_) {
      case Phase::Halo:
        out = hydrology::ring_message(std::span<const double>(z_), rect_);
        break;
      case Phase::Pits:
        bytes::put(out, static_cast<std::uint8_t>(has_pit()));
        break;
      case Phase::Basins:
        out = hydrology::basin_links_message(basins_);
        break;
      case Phase::Terminals:
        bytes::put_vector(out, pits_ending_at_perimeter());
        break;
      case Phase::Region:
        out = region_message();
        break;
      case Phase::Spill:
        out = hydrology::encode(flood_.graph);
        break;
      case Phase::Epsilon:
        out = epsilon_->message();
        break;
      case Phase::Ring:
        out = hydrology::ring_message(std::span<const float>(surface_), rect_);
        break;
      case Phase::Accumulate:
        out = hydrology::accumulation_message(accumulation_);
        accumulation_.local = {};  // only the message needs the local counts
        break;
      case Phase::Incise:
        out = finished_message();
        break;
      case Phase::Maximum:
        bytes::put(out, *std::max_element(count_.begin(), count_.end()));
        break;
      case Phase::Done:
        throw std::logic_error("stream power across tiles: a message after the last round");
    }
    return hydrology::tagged(phase_, std::move(out));
  }

  void answer(int, std::string_view bytes) override {
    switch (phase_) {
      case Phase::Halo:
        ringed_z_ = hydrology::with_ring(std::span<const double>(z_), rect_, whole_, bytes);
        if (substep_ < schedule_.diff_steps) {
          diffuse();
          ++substep_;
        } else {
          phase_ = Phase::Pits;
        }
        return;
      case Phase::Pits:
        // The routed surface is the heights in float, ring included, unless a fill raises some.
        ringed_surface_.resize(ringed_z_.size());
        for (std::size_t k = 0; k < ringed_z_.size(); ++k) ringed_surface_[k] = static_cast<float>(ringed_z_[k]);
        if (bytes::take<std::uint8_t>(bytes, kWhat) != 0) {
          // Which cells drain to a pit: the D8 paths of the surface as it is, joined across the tiles.
          pre_direction_ = directions();
          basins_ = hydrology::start_tile_basins(hydrology::start_tile_accumulation(pre_direction_, rect_, whole_));
          phase_ = Phase::Basins;
        } else {
          after_fill();
        }
        break;
      case Phase::Basins:
        hydrology::take_basin_outlets(basins_, bytes);
        phase_ = Phase::Terminals;
        break;
      case Phase::Terminals: {
        // A cell is in a pit basin when its path ends at a pit: one of the tile's own, or one another tile named.
        std::vector<std::int64_t> pits = bytes::take_vector<std::int64_t>(bytes, kWhat);
        hydrology::expect_end(bytes, kWhat);
        const std::vector<std::int64_t> own = own_pits();
        pits.insert(pits.end(), own.begin(), own.end());
        std::sort(pits.begin(), pits.end());
        in_basin_.assign(n_, 0);
        for (std::size_t k = 0; k < n_; ++k)
          in_basin_[k] = std::binary_search(pits.begin(), pits.end(), basins_.outlet[k]);
        basins_ = {};
        pre_direction_ = {};
        phase_ = Phase::Region;
        break;
      }
      case Phase::Region:
        if (bytes::take<std::uint8_t>(bytes, kWhat) != 0) {
          // Too large to gather: the fill across the tiles, of the pit basins alone (every other cell keeps its
          // height, nodes/hydrology/pit_basin_fill.h).
          hydrology::expect_end(bytes, kWhat);
          surface_.resize(n_);
          drained_.resize(n_);
          for (std::size_t k = 0; k < n_; ++k) {
            surface_[k] = static_cast<float>(z_[k]);
            drained_[k] = !in_basin_[k];
          }
          flood_ = hydrology::flood_tile(surface_, rect_, drained_);
          phase_ = Phase::Spill;
        } else {
          take_region_fill(bytes);
          after_fill();
        }
        break;
      case Phase::Spill:
        epsilon_ = std::make_unique<hydrology::TileEpsilon>(
            hydrology::apply_spill_levels(flood_, bytes::take_vector<float>(bytes, kWhat)), rect_, whole_, drained_);
        flood_ = {};
        drained_ = {};
        phase_ = Phase::Epsilon;
        break;
      case Phase::Epsilon: {
        const bool again = bytes::take<std::uint8_t>(bytes, kWhat) != 0;
        epsilon_->answer(bytes);
        if (again) return;
        surface_ = epsilon_->surface();
        epsilon_.reset();
        // As the whole-domain run: a raised cell takes the filled height, and the raise counts as deposition.
        for (std::size_t k = 0; k < n_; ++k)
          if (surface_[k] != static_cast<float>(z_[k])) {
            dep_[k] += static_cast<double>(surface_[k]) - z_[k];
            z_[k] = surface_[k];
          }
        if (finishing_) {
          phase_ = Phase::Maximum;
        } else {
          phase_ = Phase::Ring;
        }
        return;
      }
      case Phase::Ring:
        ringed_surface_ = hydrology::with_ring(std::span<const float>(surface_), rect_, whole_, bytes);
        surface_ = {};
        after_fill();
        break;
      case Phase::Accumulate: {
        count_ = hydrology::finish_tile_accumulation(accumulation_, bytes);
        accumulation_ = {};
        area_.resize(n_);
        for (std::size_t k = 0; k < n_; ++k) area_[k] = static_cast<double>(count_[k]) * grid_.cell_area();
        start_incision();
        phase_ = Phase::Incise;
        return;
      }
      case Phase::Incise: {
        const bool again = bytes::take<std::uint8_t>(bytes, kWhat) != 0;
        take_finished(bytes);
        if (again) return;
        if (std::find(done_.begin(), done_.end(), std::uint8_t{0}) != done_.end())
          throw std::logic_error("stream power across tiles: cells left without a receiver's height");
        if (++step_ < schedule_.steps) {
          start_step();
        } else {
          // The last routing's fill of the result in float, with the base level of the result.
          finishing_ = true;
          for (std::size_t k = 0; k < n_; ++k) outlet_[k] = fixed_[k] || z_[k] < p_.sea_level;
          phase_ = Phase::Halo;
        }
        return;
      }
      case Phase::Maximum:
        largest_ = bytes::take<std::int64_t>(bytes, kWhat);
        hydrology::expect_end(bytes, kWhat);
        phase_ = Phase::Done;
        return;
      case Phase::Done:
        throw std::logic_error("stream power across tiles: an answer after the last round");
    }
    (void)bytes;
  }

  std::vector<PortValue> outputs() override {
    if (phase_ != Phase::Done) throw std::logic_error("stream power across tiles: outputs before the last round");
    auto out = std::make_shared<Heightfield>(domain_), erosion = std::make_shared<Heightfield>(domain_),
         deposition = std::make_shared<Heightfield>(domain_), flow = std::make_shared<Heightfield>(domain_),
         accumulation = std::make_shared<Heightfield>(domain_);
    // As the whole-domain maps: the flow map is log(area) over the log of the largest area in cells.
    const double dx = whole_spacing_.x, dy = whole_spacing_.y;
    const double amax = std::max(dx * dy, static_cast<double>(largest_) * grid_.cell_area());
    const double lmax = std::log(amax / (dx * dy));
    for (std::size_t k = 0; k < n_; ++k) {
      out->data[k] = static_cast<float>(z_[k]);
      erosion->data[k] = static_cast<float>(ero_[k]);
      deposition->data[k] = static_cast<float>(dep_[k]);
      flow->data[k] = lmax > 0 ? static_cast<float>(std::log(area_[k] / (dx * dy)) / lmax) : 0.0f;
      accumulation->data[k] = static_cast<float>(area_[k]);
    }
    return {HeightfieldPtr(out), HeightfieldPtr(erosion), HeightfieldPtr(deposition), HeightfieldPtr(flow),
            HeightfieldPtr(accumulation)};
  }

 private:
  // Uplift and the base level after it (the domain's border and the cells under sea level), then the diffusion
  // sub-steps' halos.
  void start_step() {
    for (std::size_t k = 0; k < n_; ++k) {
      z_[k] += ufac_[k] * schedule_.dt;
      outlet_[k] = fixed_[k] || z_[k] < p_.sea_level;
    }
    substep_ = 0;
    phase_ = Phase::Halo;
  }

  // One explicit diffusion sub-step of the tile's samples from the ringed heights (mirrored across the domain's
  // border, as on the whole domain).
  void diffuse() {
    const double c = p_.diffusion * schedule_.dt / schedule_.diff_steps;
    const double cx = 1.0 / (whole_spacing_.x * whole_spacing_.x), cy = 1.0 / (whole_spacing_.y * whole_spacing_.y);
    const glm::ivec2 at = rect_.first - ringed_.first;
    const std::size_t rw = static_cast<std::size_t>(ringed_.size.x);
    for (int j = 0; j < rect_.size.y; ++j) {
      const int gj = rect_.first.y + j;
      for (int i = 0; i < rect_.size.x; ++i) {
        const int gi = rect_.first.x + i;
        const std::size_t k = static_cast<std::size_t>(j) * rect_.size.x + i;
        const std::size_t q = static_cast<std::size_t>(at.y + j) * rw + static_cast<std::size_t>(at.x + i);
        const double zc = ringed_z_[q];
        const double zw = gi > 0 ? ringed_z_[q - 1] : zc, ze = gi < whole_.x - 1 ? ringed_z_[q + 1] : zc;
        const double zs = gj > 0 ? ringed_z_[q - rw] : zc, zn = gj < whole_.y - 1 ? ringed_z_[q + rw] : zc;
        const double dz = diffusion_change(outlet_[k], c, kfac_[k], cx, cy, zc, zw, ze, zs, zn);
        z_[k] = zc + dz;
        ero_[k] += std::max(-dz, 0.0);
        dep_[k] += std::max(dz, 0.0);
      }
    }
  }

  // Whether a cell of the tile other than the base level has no strictly lower 8-neighbour in float.
  bool has_pit() const {
    const glm::ivec2 at = rect_.first - ringed_.first;
    auto zf = [&](int x, int y) {
      return static_cast<float>(ringed_z_[static_cast<std::size_t>(y) * ringed_.size.x + static_cast<std::size_t>(x)]);
    };
    for (int j = 0; j < rect_.size.y; ++j)
      for (int i = 0; i < rect_.size.x; ++i) {
        if (outlet_[static_cast<std::size_t>(j) * rect_.size.x + i]) continue;
        const int x = at.x + i, y = at.y + j;
        const float z = zf(x, y);
        bool lower = false;
        for (int d = 0; d < 8 && !lower; ++d) lower = zf(x + hydrology::kDi[d], y + hydrology::kDj[d]) < z;
        if (!lower) return true;
      }
    return false;
  }

  // The D8 directions of the tile's cells over the ringed surface (the ringed tile as a grid of its own: its border
  // cells are outlets only where the domain's border is, and every neighbour of the tile's cells is in it).
  // A cell's direction depends on its own base-level flag alone, so the ring's flags are left 0.
  std::vector<std::uint8_t> directions() const {
    const FlowGrid g(ringed_.size.x, ringed_.size.y, grid_.dx, grid_.dy);
    std::vector<std::uint8_t> base(ringed_surface_.size(), 0);
    const glm::ivec2 at = rect_.first - ringed_.first;
    for (int j = 0; j < rect_.size.y; ++j)
      std::copy_n(outlet_.begin() + static_cast<std::ptrdiff_t>(j) * rect_.size.x, rect_.size.x,
                  base.begin() + static_cast<std::ptrdiff_t>(at.y + j) * ringed_.size.x + at.x);
    hydrology::Outlets outlets;
    outlets.mask = base;
    return hydrology::without_ring<std::uint8_t>(hydrology::d8_flow(g, ringed_surface_, outlets).direction, rect_,
                                                 whole_);
  }

  // The tile's pits (cells other than the base level without a direction), as domain samples in increasing order.
  std::vector<std::int64_t> own_pits() const {
    std::vector<std::int64_t> pits;
    for (std::size_t k = 0; k < n_; ++k)
      if (!outlet_[k] && pre_direction_[k] == hydrology::kNoDirection)
        pits.push_back(hydrology::domain_sample(rect_, whole_, static_cast<std::int32_t>(k)));
    return pits;
  }

  // The tile's pits where paths from its perimeter end: the only ones whose basins other tiles may share.
  std::vector<std::int64_t> pits_ending_at_perimeter() const {
    const std::vector<std::int64_t> own = own_pits();
    std::vector<std::int64_t> ends;
    for (const std::int32_t c : hydrology::perimeter_cells(rect_.size)) {
      const std::int64_t t = basins_.outlet[static_cast<std::size_t>(c)];
      if (std::binary_search(own.begin(), own.end(), t)) ends.push_back(t);
    }
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    return ends;
  }

  // The tile's cells in pit basins with their 8-neighbours outside them (those in the ring may lie in a basin
  // another tile sends), or only a flag when they are too many to gather.
  std::string region_message() const {
    std::string out;
    hydrology::put_tile_rect(out, rect_);
    const auto inside = static_cast<std::size_t>(std::count(in_basin_.begin(), in_basin_.end(), std::uint8_t{1}));
    const bool large = inside > region_limit_;
    bytes::put(out, static_cast<std::uint8_t>(large));
    if (large) return out;
    const glm::ivec2 at = rect_.first - ringed_.first;
    std::vector<std::int64_t> samples;
    std::vector<float> heights;
    std::vector<std::uint8_t> flags;
    auto add = [&](int x, int y, bool in) {  // ringed coordinates
      samples.push_back(static_cast<std::int64_t>(ringed_.first.y + y) * whole_.x + ringed_.first.x + x);
      heights.push_back(ringed_surface_[static_cast<std::size_t>(y) * ringed_.size.x + static_cast<std::size_t>(x)]);
      flags.push_back(in);
    };
    for (int j = 0; j < rect_.size.y; ++j)
      for (int i = 0; i < rect_.size.x; ++i) {
        if (!in_basin_[static_cast<std::size_t>(j) * rect_.size.x + i]) continue;
        add(at.x + i, at.y + j, true);
        for (int d = 0; d < 8; ++d) {
          const int x = at.x + i + hydrology::kDi[d], y = at.y + j + hydrology::kDj[d];
          if (x < 0 || y < 0 || x >= ringed_.size.x || y >= ringed_.size.y) continue;
          const int ti = x - at.x, tj = y - at.y;
          const bool own = ti >= 0 && tj >= 0 && ti < rect_.size.x && tj < rect_.size.y;
          if (!own || !in_basin_[static_cast<std::size_t>(tj) * rect_.size.x + ti]) add(x, y, false);
        }
      }
    bytes::put_vector(out, samples);
    bytes::put_vector(out, heights);
    bytes::put_vector(out, flags);
    return out;
  }

  // The filled heights of the pit basins' samples on the ringed tile: the surface there, and on the tile's own
  // cells the heights, the raise counting as deposition (as the whole-domain run does).
  void take_region_fill(std::string_view bytes) {
    const auto [samples, heights] = SampleHeights<float>::take(bytes);
    hydrology::expect_end(bytes, kWhat);
    const glm::ivec2 at = rect_.first - ringed_.first;
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const int x = static_cast<int>(samples[s] % whole_.x) - ringed_.first.x,
                y = static_cast<int>(samples[s] / whole_.x) - ringed_.first.y;
      if (x < 0 || y < 0 || x >= ringed_.size.x || y >= ringed_.size.y)
        throw std::invalid_argument("stream power across tiles: a filled sample outside the tile");
      ringed_surface_[static_cast<std::size_t>(y) * ringed_.size.x + static_cast<std::size_t>(x)] = heights[s];
      const int i = x - at.x, j = y - at.y;
      if (i < 0 || j < 0 || i >= rect_.size.x || j >= rect_.size.y) continue;
      const std::size_t k = static_cast<std::size_t>(j) * rect_.size.x + static_cast<std::size_t>(i);
      if (heights[s] != static_cast<float>(z_[k])) {
        dep_[k] += static_cast<double>(heights[s]) - z_[k];
        z_[k] = heights[s];
      }
    }
  }

  // The float surface is final on the tile and its ring: the D8 directions, then the counts (or, after the last
  // step, the largest area).
  void after_fill() {
    if (finishing_) {
      phase_ = Phase::Maximum;
      return;
    }
    direction_ = directions();
    ringed_surface_ = {};
    accumulation_ = hydrology::start_tile_accumulation(direction_, rect_, whole_);
    phase_ = Phase::Accumulate;
  }

  // The receivers within the tile and their donors; the cells that need no receiver's height are done at once
  // (outlets and cells below the channel area keep theirs), and the walk goes up from them.
  void start_incision() {
    receiver_.assign(n_, -1);
    std::vector<std::int32_t> donor_count(n_ + 1, 0);
    for (std::size_t k = 0; k < n_; ++k) {
      const std::uint8_t d = direction_[k];
      if (d == hydrology::kNoDirection) {
        receiver_[k] = static_cast<std::int32_t>(k);
        continue;
      }
      const int i = static_cast<int>(k % rect_.size.x) + hydrology::kDi[d],
                j = static_cast<int>(k / rect_.size.x) + hydrology::kDj[d];
      if (i < 0 || j < 0 || i >= rect_.size.x || j >= rect_.size.y) continue;  // held by another tile too
      receiver_[k] = j * rect_.size.x + i;
      ++donor_count[static_cast<std::size_t>(receiver_[k])];
    }
    donor_start_.assign(n_ + 1, 0);
    for (std::size_t k = 0; k < n_; ++k) donor_start_[k + 1] = donor_start_[k] + donor_count[k];
    donors_.resize(static_cast<std::size_t>(donor_start_[n_]));
    std::vector<std::int32_t> fill(donor_start_.begin(), donor_start_.end() - 1);
    for (std::size_t k = 0; k < n_; ++k) {
      const std::int32_t r = receiver_[k];
      if (r >= 0 && r != static_cast<std::int32_t>(k))
        donors_[static_cast<std::size_t>(fill[r]++)] = static_cast<std::int32_t>(k);
    }
    done_.assign(n_, 0);
    walk_.clear();
    for (std::size_t k = 0; k < n_; ++k)
      if (receiver_[k] == static_cast<std::int32_t>(k) || !incision_->incises(area_[k])) {
        done_[k] = 1;
        walk_.push_back(static_cast<std::int32_t>(k));
      }
    walk_up();
  }

  // Incises the donors of the cells on the walk, and theirs, each from its receiver's final height.
  void walk_up() {
    while (!walk_.empty()) {
      const std::int32_t r = walk_.back();
      walk_.pop_back();
      for (std::int32_t q = donor_start_[r]; q < donor_start_[r + 1]; ++q) {
        const std::int32_t k = donors_[static_cast<std::size_t>(q)];
        if (done_[k]) continue;
        const double z0 = z_[k];
        const double zn = incision_->incised(z0, z_[r], area_[k], kfac_[k], direction_[k]);
        ero_[k] += z0 - zn;
        z_[k] = zn;
        done_[k] = 1;
        walk_.push_back(k);
        if (on_perimeter(k)) finished_.push_back(k);
      }
    }
  }

  bool on_perimeter(std::int32_t k) const {
    const int i = k % rect_.size.x, j = k / rect_.size.x;
    return i == 0 || j == 0 || i == rect_.size.x - 1 || j == rect_.size.y - 1;
  }

  // The perimeter samples incised since the last message, as domain sample indices and heights.
  std::string finished_message() {
    SampleHeights<double> finished;
    for (const std::int32_t k : finished_)
      finished.push(hydrology::domain_sample(rect_, whole_, k), z_[static_cast<std::size_t>(k)]);
    finished_.clear();
    std::string out;
    hydrology::put_tile_rect(out, rect_);
    finished.put(out);
    return out;
  }

  // Shared samples other tiles incised: their heights, and the walk up from them.
  void take_finished(std::string_view bytes) {
    const auto [samples, heights] = SampleHeights<double>::take(bytes);
    hydrology::expect_end(bytes, kWhat);
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const std::int64_t x = samples[s] % whole_.x - rect_.first.x, y = samples[s] / whole_.x - rect_.first.y;
      if (x < 0 || y < 0 || x >= rect_.size.x || y >= rect_.size.y)
        throw std::invalid_argument("stream power across tiles: a height for a sample outside the tile");
      const auto k = static_cast<std::int32_t>(y * rect_.size.x + x);
      if (done_[k]) continue;
      ero_[k] += z_[k] - heights[s];
      z_[k] = heights[s];
      done_[k] = 1;
      walk_.push_back(k);
    }
    walk_up();
  }

  StreamPowerParams p_;
  StreamPowerSchedule schedule_;
  std::shared_ptr<const StreamPowerIncision> incision_;
  Domain domain_;
  glm::ivec2 whole_;
  glm::dvec2 whole_spacing_;
  FlowGrid grid_;
  TileRect rect_, ringed_;
  std::size_t n_ = 0;
  std::size_t region_limit_ = 0;  // the most cells in pit basins the tile sends to be filled in one piece
  Phase phase_ = Phase::Halo;
  int step_ = 0, substep_ = 0;
  bool finishing_ = false;
  std::vector<double> z_, ero_, dep_, kfac_, ufac_, area_;
  std::vector<std::uint8_t> fixed_;    // the domain's border: base level always
  std::vector<std::uint8_t> outlet_;   // base level this step: fixed, or under sea level after the uplift
  std::vector<double> ringed_z_;       // the heights with their ring, from the last halo
  std::vector<float> surface_;         // the filled float surface on the tile
  std::vector<float> ringed_surface_;  // and with its ring
  hydrology::TileBasins basins_;
  std::vector<std::uint8_t> in_basin_;  // per tile cell: its D8 path ends in a pit
  std::vector<std::uint8_t> drained_;   // the others, while the fill runs across the tiles
  hydrology::TileFlood flood_;
  std::unique_ptr<hydrology::TileEpsilon> epsilon_;
  std::vector<std::uint8_t> direction_, pre_direction_;  // D8 over the filled surface, and before the fill
  hydrology::TileAccumulation accumulation_;
  std::vector<std::int64_t> count_;
  std::int64_t largest_ = 0;
  // Incision: the receiver in the tile (-1 outside it, itself at an outlet), the donors, what is done.
  std::vector<std::int32_t> receiver_, donor_start_, donors_, walk_, finished_;
  std::vector<std::uint8_t> done_;
};

class StreamPowerAcrossTiles : public TileGraphAlgorithm {
 public:
  StreamPowerAcrossTiles(const StreamPowerParams& p, const Domain& whole, std::optional<std::size_t> region_limit)
      : p_(p),
        region_limit_(region_limit),
        whole_(whole),
        schedule_(StreamPowerSchedule::of(p, whole.spacing.x, whole.spacing.y, whole.sample_count())),
        incision_(std::make_shared<StreamPowerIncision>(p, FlowGrid::of(whole), schedule_.dt)) {}

  int rounds() const override { return 1; }

  // Every tile is in the same phase; the run ends with the largest area.
  bool another_round(int, const std::vector<std::string>& messages) const override {
    if (messages.empty()) return false;
    std::string_view first(messages.front());
    return take_phase(first) != Phase::Maximum;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const HeightfieldPtr in = tile_heightfield(inputs, 0), mask = tile_heightfield(inputs, 1),
                         uplift = tile_heightfield(inputs, 2);
    if (!in) throw std::invalid_argument("stream power across tiles needs a heightfield input");
    for (const auto& f : {mask, uplift})
      if (f && f->domain.resolution != in->domain.resolution)
        throw std::invalid_argument("stream power across tiles: mask and uplift must lie on the tile");
    if (in->width() < 2 || in->height() < 2)
      throw std::invalid_argument("stream power across tiles: a tile narrower than 2 samples");
    require_finite_inputs("StreamPower", {{"in", in.get()}, {"uplift", uplift.get()}, {"mask", mask.get()}});
    return std::make_unique<StreamPowerTile>(*in, mask.get(), uplift.get(), p_, schedule_, incision_, whole_,
                                             region_limit_);
  }

  std::vector<std::string> solve(int, const std::vector<std::string>& messages) const override {
    const auto untagged = hydrology::untag_messages<Phase>(messages, kWhat, kWhat);
    const auto& views = untagged.views;
    const glm::ivec2 whole = whole_.resolution;
    switch (untagged.phase) {
      case Phase::Halo:
        return hydrology::solve_double_rings(views, whole);
      case Phase::Pits:
      case Phase::Maximum:
        return same_answer(untagged.phase, views);
      case Phase::Basins:
        return hydrology::solve_basin_links(views, whole);
      case Phase::Terminals: {
        // Every tile's pits that paths from its perimeter end at, to every tile.
        std::vector<std::int64_t> pits;
        for (std::string_view v : views) {
          const auto p = bytes::take_vector<std::int64_t>(v, kWhat);
          hydrology::expect_end(v, kWhat);
          pits.insert(pits.end(), p.begin(), p.end());
        }
        std::sort(pits.begin(), pits.end());
        pits.erase(std::unique(pits.begin(), pits.end()), pits.end());
        std::string answer;
        bytes::put_vector(answer, pits);
        return std::vector<std::string>(views.size(), answer);
      }
      case Phase::Region:
        return fill_regions(views);
      case Phase::Spill:
        return hydrology::solve_spill_messages(views, whole);
      case Phase::Epsilon: {
        std::vector<std::string> answers = hydrology::solve_perimeter_minima(views, whole);
        const bool fell = hydrology::perimeter_minima_fell(views);
        for (std::string& a : answers) a.insert(a.begin(), static_cast<char>(fell));
        return answers;
      }
      case Phase::Ring:
        return hydrology::solve_rings(views, whole);
      case Phase::Accumulate:
        return hydrology::solve_tile_accumulation(views, whole);
      case Phase::Incise:
        return share_finished(views);
      case Phase::Done:
        break;
    }
    throw std::invalid_argument("stream power across tiles: a message after the last round");
  }

 private:
  // The one answer of every tile: whether any tile has a pit, or the largest count.
  static std::vector<std::string> same_answer(Phase phase, const std::vector<std::string_view>& views) {
    std::string answer;
    if (phase == Phase::Pits) {
      std::uint8_t any = 0;
      for (std::string_view v : views) any |= bytes::take<std::uint8_t>(v, kWhat);
      bytes::put(answer, any);
    } else {
      std::int64_t largest = 0;
      for (std::string_view v : views) largest = std::max(largest, bytes::take<std::int64_t>(v, kWhat));
      bytes::put(answer, largest);
    }
    return std::vector<std::string>(views.size(), answer);
  }

  // The pit basins of every tile filled in one piece, each tile answered with the filled samples on it and its ring;
  // or, when a tile's basins were too large to send, the word to fill across the tiles.
  std::vector<std::string> fill_regions(const std::vector<std::string_view>& views) const {
    const glm::ivec2 whole = whole_.resolution;
    std::vector<TileRect> rects;
    std::vector<hydrology::BasinSample> samples;
    bool large = false;
    for (std::string_view in : views) {
      rects.push_back(hydrology::take_tile_rect(in, whole, kWhat));
      if (bytes::take<std::uint8_t>(in, kWhat) != 0) {
        large = true;
        hydrology::expect_end(in, kWhat);
        continue;
      }
      const auto s = bytes::take_vector<std::int64_t>(in, kWhat);
      const auto h = bytes::take_vector<float>(in, kWhat);
      const auto f = bytes::take_vector<std::uint8_t>(in, kWhat);
      hydrology::expect_end(in, kWhat);
      if (s.size() != h.size() || s.size() != f.size())
        throw std::invalid_argument("stream power across tiles: truncated pit basins");
      if (!large)
        for (std::size_t q = 0; q < s.size(); ++q) samples.push_back({s[q], h[q], f[q] != 0});
    }
    std::vector<std::string> answers(views.size());
    if (large) {
      for (std::string& a : answers) bytes::put(a, std::uint8_t{1});
      return answers;
    }
    const auto filled = hydrology::fill_pit_basins(std::move(samples), whole);
    for (std::size_t t = 0; t < views.size(); ++t) {
      const TileRect ringed = hydrology::ringed_rect(rects[t], whole);
      SampleHeights<float> mine;
      for (const auto& [sample, height] : filled)
        if (holds(ringed, static_cast<int>(sample % whole.x), static_cast<int>(sample / whole.x)))
          mine.push(sample, height);
      bytes::put(answers[t], std::uint8_t{0});
      mine.put(answers[t]);
    }
    return answers;
  }

  // Each tile's finished shared samples to the other tiles holding them, and whether any tile sent one.
  std::vector<std::string> share_finished(const std::vector<std::string_view>& views) const {
    const glm::ivec2 whole = whole_.resolution;
    const std::size_t count = views.size();
    std::vector<TileRect> rects(count);
    std::vector<SampleHeights<double>> sent(count), received(count);
    for (std::size_t t = 0; t < count; ++t) {
      std::string_view in = views[t];
      rects[t] = hydrology::take_tile_rect(in, whole, kWhat);
      sent[t] = SampleHeights<double>::take(in);
      hydrology::expect_end(in, kWhat);
    }
    bool any = false;
    for (std::size_t t = 0; t < count; ++t) {
      any = any || !sent[t].samples.empty();
      for (std::size_t q = 0; q < sent[t].samples.size(); ++q) {
        const std::int64_t s = sent[t].samples[q];
        if (s < 0 || s >= static_cast<std::int64_t>(whole.x) * whole.y)
          throw std::invalid_argument("stream power across tiles: a sample outside the domain");
        const int x = static_cast<int>(s % whole.x), y = static_cast<int>(s / whole.x);
        for (std::size_t u = 0; u < count; ++u)
          if (u != t && holds(rects[u], x, y)) received[u].push(s, sent[t].heights[q]);
      }
    }
    std::vector<std::string> answers(count);
    for (std::size_t u = 0; u < count; ++u) {
      bytes::put(answers[u], static_cast<std::uint8_t>(any));
      received[u].put(answers[u]);
    }
    return answers;
  }

  StreamPowerParams p_;
  std::optional<std::size_t> region_limit_;
  Domain whole_;
  StreamPowerSchedule schedule_;
  std::shared_ptr<const StreamPowerIncision> incision_;
};

StreamPowerParams params_of(const ParamView& v) {
  StreamPowerParams p;
  p.k = v.get<double>("k");
  p.m = v.get<double>("m");
  p.n = v.get<double>("n");
  p.uplift = v.get<double>("uplift_rate");
  p.diffusion = v.get<double>("diffusion");
  p.dt = v.get<double>("time_step");
  p.duration = v.get<double>("duration");
  p.sea_level = v.get<double>("sea_level");
  p.channel_area = v.get<double>("channel_area");
  p.depressions = StreamPowerParams::Depressions::PriorityFlood;
  return p;
}

// With the Priority-Flood fill; a run the whole-domain node would refuse (too many steps) stays on the whole domain,
// whose node reports why.
const bool kStreamPowerRegistered = register_tile_graph(
    "StreamPower",
    [](const ParamView& v, const Domain& whole) {
      if (v.get<std::string>("depressions") != "priority_flood") return std::unique_ptr<TileGraphAlgorithm>();
      return stream_power_across_tiles(params_of(v), whole);
    },
    "with depressions 'priority_flood'");

}  // namespace

std::unique_ptr<TileGraphAlgorithm> stream_power_across_tiles(const StreamPowerParams& p, const Domain& whole,
                                                              std::optional<std::size_t> largest_gathered_basins) {
  if (p.depressions != StreamPowerParams::Depressions::PriorityFlood)
    throw std::invalid_argument("stream power across tiles: only with the Priority-Flood fill");
  return std::make_unique<StreamPowerAcrossTiles>(p, whole, largest_gathered_basins);
}

}  // namespace orogen::erosion
