#pragma once
// Choices shared by the noise generators, their kernels and their nodes.
#include <array>
#include <string_view>

namespace orogen::noise {

// A single-octave lattice noise. Ranges of the unscaled noise:
//   Perlin, Simplex, Value, White: [-1, 1];  Worley: distances >= 0 in lattice cells.
enum class Basis { Perlin, Simplex, Value, White, Worley };

enum class WorleyMetric { Euclidean, Manhattan, Chebyshev };

// What a Worley generator outputs, from the distances F1 <= F2 <= F3 <= F4 to the nearest feature points.
enum class WorleyOutput { F1, F2, F2MinusF1, F1TimesF2, MeanF1ToF4 };

// How octaves combine (see fbm.h).
enum class FractalMode { Fbm, Ridged, Billow, Hybrid, Multifractal };

// Names as they appear in graph files (enum parameter choices), in enum order.
inline constexpr std::array<std::string_view, 5> kBasisNames{"perlin", "simplex", "value", "white", "worley"};
inline constexpr std::array<std::string_view, 3> kWorleyMetricNames{"euclidean", "manhattan", "chebyshev"};
inline constexpr std::array<std::string_view, 5> kWorleyOutputNames{"f1", "f2", "f2_minus_f1", "f1_times_f2",
                                                                    "mean_f1_f4"};
inline constexpr std::array<std::string_view, 5> kFractalModeNames{"fbm", "ridged", "billow", "hybrid", "multifractal"};

// How many nearest distances an output needs (1, 2 or 4).
constexpr int worley_rank(WorleyOutput o) {
  switch (o) {
    case WorleyOutput::F1:
      return 1;
    case WorleyOutput::MeanF1ToF4:
      return 4;
    default:
      return 2;
  }
}

}  // namespace orogen::noise
