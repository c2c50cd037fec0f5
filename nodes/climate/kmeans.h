#pragma once
// K-means clustering of per-cell feature vectors (Lloyd's algorithm: S. P. Lloyd (1982), Least squares
// quantization in PCM), as H. Long (2016), Using procedural methods to generate realistic virtual rural
// worlds (chapter 4), clusters resource vectors into ecosystems: weighted squared distance
// D(a, b) = sum_c w_c (a_c - b_c)^2, deterministic initial centres along the terrain diagonal or k-means++
// from a seed (D. Arthur, S. Vassilvitskii (2007), k-means++: the advantages of careful seeding).
//
// Iterates until at most `tolerance` x cells change cluster in an assignment (0: none) or max_iterations.
// Deterministic for any thread count and any tiling: assignment is per cell (float distances); the new means are the
// exact sums of the members' features (ExactFloatSum, independent of the order of addition) rounded once to double,
// divided by the member count (nodes/climate/kmeans_steps.h). Empty clusters keep their centre. Ties go to the lower
// cluster id. Non-finite features count as 0.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::climate {

enum class KMeansInit { Diagonal, PlusPlus };

struct KMeansParams {
  int k = 6;  // 1..64
  int max_iterations = 100;
  double tolerance = 0.0;  // converged when at most this fraction of the cells changed cluster
  KMeansInit init = KMeansInit::Diagonal;
  std::uint64_t seed = 0;
  std::vector<double> weights;  // per channel; empty = all 1
};

struct KMeansResult {
  int k = 0, channels = 0;
  std::vector<std::int32_t> labels;  // per cell, 0..k-1; -1 for a cell with a NaN or infinite feature
  std::vector<double> centres;       // k x channels, feature units
  std::vector<std::int64_t> counts;  // per cluster
  std::vector<double> objective;     // sum of weighted squared distances after each assignment
  int iterations = 0;
  bool converged = false;
};

KMeansResult kmeans(const Image& features, const KMeansParams& p, const ExecContext* ctx = nullptr);

// Per-channel weights from the resource groups of channel names ("slope", "temperature_*",
// "illumination_*", "humidity_*", anything else).
std::vector<double> group_weights(const std::vector<std::string>& names, int channels, double slope, double temperature,
                                  double illumination, double humidity, double other);

// The clustering on the features' domain: the cluster id of each cell as a float field, and its categorical
// color (nodes/common/categorical_palette.h) as a linear RGBA image.
struct KMeansMaps {
  std::shared_ptr<Heightfield> ids;
  std::shared_ptr<Image> color;
};
KMeansMaps kmeans_maps(const KMeansResult& r, const Domain& domain);

// The report JSON: k, iterations, converged, objective per iteration, and per cluster its id, member count,
// color (linear RGB) and centre by channel name (channel_<c> beyond the names). Non-finite numbers are null.
std::string kmeans_report(const KMeansResult& r, const std::vector<std::string>& channel_names);

}  // namespace orogen::climate
