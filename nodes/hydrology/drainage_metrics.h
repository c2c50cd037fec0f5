#pragma once
// DrainageMetrics: realism figures of a drainage network, comparable with real basins (Horton 1945,
// Strahler 1957, Hack 1957, Flint 1974).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

struct LogFit {
  double slope = NAN, intercept = NAN, r2 = NAN;
  int points = 0;  // bins used
};

// Least-squares line through log10(y) against log10(x) over bins of log10(x) `bin_width` wide: each bin with at
// least `min_count` samples contributes the mean of log10(y) at the mean of its log10(x). Samples with x or y
// not positive are ignored.
LogFit binned_log_fit(std::span<const double> x, std::span<const double> y, double bin_width = 0.1, int min_count = 3);

struct NetworkMetrics {
  std::size_t cells = 0;
  std::size_t channel_cells = 0;
  int max_order = 0;
  std::vector<int> stream_counts;          // Horton N_w, w = 1..max_order
  std::vector<double> mean_stream_length;  // m, w = 1..max_order
  double bifurcation_ratio = NAN;          // R_b from log N_w against w
  double length_ratio = NAN;               // R_L from log mean length against w
  LogFit hack;                             // main-stream length L = c A^h over channel cells: slope = h
  LogFit flint;                            // S = k A^-theta over channel cells: slope = -theta
  std::vector<std::int32_t> order;         // Strahler order per cell (0 off the network)
};

// What the figures of a network are made of, channel cell by channel cell in reverse stack order (upstream first):
// Horton streams (their order and length, m), and per channel cell its area (m^2) and main-stream length (m), and
// where it has a receiver outside lakes its area and slope.
struct NetworkSamples {
  std::size_t channel_cells = 0;
  std::vector<int> stream_order;
  std::vector<double> stream_length;
  std::vector<double> area, main_length;
  std::vector<double> slope_area, slope;
};

// One channel cell as network_metrics samples it.
struct ChannelSample {
  std::int32_t same = -1;  // its channel donor of its order, whose Horton stream it continues; -1: a stream starts
  int order = 0;           // Strahler
  double step = 0.0;       // the distance to its receiver, 0 at an outlet
  double area = 0.0, main_length = 0.0;
  std::optional<double> slope;  // for Flint's fit: none at an outlet or where left out (lakes)
};
// Adds channel cell c to the samples, the cells visited upstream first; `stream` (per cell) gets its Horton stream.
void add_channel_sample(NetworkSamples& s, std::span<std::int32_t> stream, std::size_t c, const ChannelSample& cell);

// The figures of a network of `cells` cells from its samples (every field of NetworkMetrics but `order`), as
// network_metrics computes them: the sums run in the samples' order.
NetworkMetrics network_figures(const NetworkSamples& s, std::size_t cells);

// Metrics of the network of channel cells (channel[c] != 0; receivers of channel cells must be channel cells).
// `z` gives the channel slopes (cells with `exclude_slope` set, e.g. lakes, are left out of Flint's fit).
NetworkMetrics network_metrics(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> stack,
                               std::span<const std::uint8_t> channel, std::span<const double> area,
                               std::span<const float> z, std::span<const std::uint8_t> exclude_slope = {});

// A depression (connected cells the Priority-Flood fill raises) is a lake when it is at least `depth` deep
// (spill level minus its lowest cell, m) and covers at least `area` (m^2); shallower or smaller ones are
// artefacts of the terrain (dents and dams a few cells wide) and their pits count against it.
struct LakeThreshold {
  double depth = 2.0;     // m
  double area = 40000.0;  // m^2 (4 ha)
};

struct DrainageReport {
  double pits_per_million = 0.0;                // interior cells without a lower neighbour in the input, per 10^6 cells
  double pits_outside_lakes_per_million = 0.0;  // the same, leaving out pits inside lakes
  std::size_t lakes = 0;                        // depressions that pass the lake threshold
  std::size_t depressions = 0;                  // all depressions
  double lake_cells_fraction = 0.0;
  LakeThreshold lake;
  double threshold = 0.0;
  NetworkMetrics network;
  std::string json() const;
};

// Pits are counted on the input; the network comes from D8 on the Priority-Flood+epsilon filled input, with
// channels where the contributing area reaches `threshold` (m^2).
// Pits inside depressions that pass `lake` are counted as lakes (pits_outside_lakes_per_million leaves them out).
DrainageReport drainage_metrics(const Heightfield& in, double threshold, const ExecContext* ctx = nullptr,
                                const LakeThreshold& lake = {});

}  // namespace orogen::hydrology
