#pragma once
// Channel networks on the D8 receiver tree: Strahler orders, reaches (source/confluence -> confluence/outlet),
// Horton streams. Used by RiverExtract and DrainageMetrics; plain functions over flow_routing.h.
#include <cstdint>
#include <span>
#include <vector>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

// Number of channel donors of every channel cell (0 elsewhere).
std::vector<std::uint8_t> channel_donor_counts(const FlowGrid& g, const D8Flow& f,
                                               std::span<const std::uint8_t> channel);

// Strahler order of every channel cell (0 elsewhere): 1 at sources; where two or more donors share the
// highest order o the cell has o + 1, otherwise o (Strahler 1957). `order` is stack_order(). The receiver of a
// channel cell must be a channel cell (true when channel = accumulation >= threshold).
std::vector<std::int32_t> strahler_orders(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> order,
                                          std::span<const std::uint8_t> channel);

struct Reach {
  std::vector<std::int32_t> cells;  // upstream to downstream; the last is a confluence (shared with the next
                                    // reach) or an outlet
  int parent = -1;                  // the reach this one flows into, -1 at an outlet
  int order = 0;                    // Strahler order
};

// One reach per channel segment between sources, confluences and outlets, downstream reaches first (so a
// parent's index is lower than its children's).
std::vector<Reach> extract_reaches(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> order,
                                   std::span<const std::uint8_t> channel, std::span<const std::int32_t> strahler);
// extract_reaches on any indexing of the cells (the channel cells the tiles send, nodes/hydrology/channel_network.h):
// `order` has every cell after its receiver; per cell, whether it is a channel cell, its receiver (itself at an
// outlet), its number of channel donors and its Strahler order.
std::vector<Reach> channel_reaches(std::span<const std::int32_t> order, std::span<const std::uint8_t> channel,
                                   std::span<const std::int32_t> receiver, std::span<const std::uint8_t> channel_donors,
                                   std::span<const std::int32_t> strahler);

}  // namespace orogen::hydrology
