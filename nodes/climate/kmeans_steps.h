#pragma once
// The steps of k-means (nodes/climate/kmeans.h) that the whole-domain run and the run across tiles
// (nodes/climate/kmeans_across_tiles.cpp) share, so both perform the same operations on every cell.
//
// A Lloyd iteration assigns every cell to its nearest centre (float distances, per cell) and tallies, per cluster,
// the member count and the exact sums of the members' features (ExactFloatSum): integers and exact sums do not
// depend on the order of addition, so tallies of any split of the cells (threads, tiles, ranks) add up to the same
// totals bit for bit, and the new centres (each exact sum rounded once to double, divided by the count) with them.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/image.h"
#include "nodes/climate/kmeans.h"
#include "nodes/common/exact_float_sum.h"

namespace orogen::climate {

// The features as k-means computes on them: scaled by sqrt(weight) per channel (plain squared distance
// afterwards), 0 where not finite; valid[q] is 0 for a cell with a non-finite feature (it belongs to no cluster).
struct KMeansFeatures {
  int width = 0, height = 0, channels = 0;
  std::vector<double> sw;  // sqrt(weight) per channel
  std::vector<float> x;    // cells x channels
  std::vector<char> valid;
  std::vector<std::uint8_t> tallied;  // per cell: valid and counted (the cells whose figures the tallies take in)
  // Blocks of kmeans_block cells (in row order) x channels: the block's tallied values of the channel of magnitude at
  // least fast_floor add up exactly in a double, in any order (exact_double_floor); below_floor is 1 where a tallied
  // value lies below it (non-zero, or NaN): only those go to the exact sums one by one (kmeans_assign).
  std::vector<float> fast_floor;
  std::vector<std::uint8_t> below_floor;
};
inline constexpr int kmeans_block_bits = 12;
inline constexpr std::size_t kmeans_block = std::size_t{1} << kmeans_block_bits;
// `counted`: the tallies take in the cells i < counted.x, j < counted.y (a tile counts the samples it shares with the
// tiles after it only once: they are theirs); every cell by default.
KMeansFeatures kmeans_features(const Image& features, const std::vector<double>& weights,
                               glm::ivec2 counted = glm::ivec2(std::numeric_limits<int>::max()),
                               const ExecContext* ctx = nullptr);

// The clusters' figures after an assignment.
struct KMeansTally {
  std::vector<std::int64_t> counts;  // per cluster
  std::int64_t changed = 0;          // cells whose label changed
  ExactFloatSum objective;           // of the squared distances (float) to the nearest centre
  std::vector<ExactFloatSum> sums;   // k x channels: the scaled features of the members
  std::vector<ExactFloatSum> raw;    // k x zero-weight channels, or empty: kmeans_raw_sums

  KMeansTally() = default;
  KMeansTally(int k, int channels);
  void add(const KMeansTally& o);
  // The bytes begin with `changed`.
  void put(std::string& out) const;
  // Throws std::invalid_argument on bytes that do not hold a tally of k x channels.
  static KMeansTally take(std::string_view& in, int k, int channels);
};

// Assigns every valid cell of the grid to its nearest centre (k x channels, scaled units), updating `labels`
// (one per cell of the grid), and tallies the tallied cells (without raw sums).
KMeansTally kmeans_assign(const KMeansFeatures& f, const std::vector<double>& centres, int k,
                          std::vector<std::int32_t>& labels, const ExecContext* ctx = nullptr);

// The exact sums of the unscaled features (`raw`, the unscaled image) of the zero-weight channels over the tallied
// cells by label: k x those channels (empty without any). Only the last assignment's are used: the whole-domain run
// tallies them once after its iterations.
std::vector<ExactFloatSum> kmeans_raw_sums(const KMeansFeatures& f, const Image& raw,
                                           const std::vector<std::int32_t>& labels, int k,
                                           const ExecContext* ctx = nullptr);

// Whether the assignment that gave `changed` ends the iterations: at most tolerance x cells changed cluster.
inline bool kmeans_converged(std::int64_t changed, double tolerance, std::size_t cells) {
  return static_cast<double>(changed) <= tolerance * static_cast<double>(cells);
}

// The new centres from a tally: each cluster's mean; a cluster without members keeps its centre.
void kmeans_update(const KMeansTally& t, int k, int channels, std::vector<double>& centres);

// The mean unscaled feature of each cluster (counts.size() of them) for each zero-weight channel (0 for an empty
// cluster), from their raw sums (kmeans_raw_sums): k x zero-weight channels.
std::vector<double> kmeans_raw_means(const std::vector<ExactFloatSum>& raw, const std::vector<std::int64_t>& counts);

// The result's counts and centres in feature units from the last tally's counts, the scaled centres and the
// raw means (k x zero-weight channels: kmeans_raw_means).
void kmeans_finish(const std::vector<std::int64_t>& counts, const std::vector<double>& centres,
                   const std::vector<double>& raw_means, const std::vector<double>& sw, KMeansResult& r);

// The cell of the whole grid (W x H) whose features are initial centre c of k with init diagonal.
glm::ivec2 kmeans_diagonal_cell(int c, int k, int width, int height);

}  // namespace orogen::climate
