// The shared helpers of nodes/common/: color space, hashing, trimming, hex colors, the categorical palette,
// the cancellable row loop and report building, against known values and the properties callers rely on.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include "graph/cancel.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/color_space.h"
#include "nodes/common/hash.h"
#include "nodes/common/hex_color.h"
#include "nodes/common/report_builder.h"
#include "nodes/common/smoothstep.h"
#include "nodes/common/text.h"

namespace orogen {
namespace {

// --- color_space.h ----------------------------------------------------------------------------------------

TEST(ColorSpace, KnownValues) {
  EXPECT_NEAR(srgb_to_linear(0.5), 0.21404114048223255, 1e-15);
  EXPECT_NEAR(linear_to_srgb(0.5), 0.7353569830524495, 1e-15);
  EXPECT_NEAR(srgb_to_linear(0.04045), 0.04045 / 12.92, 1e-17) << "the linear toe ends at 0.04045";
  EXPECT_NEAR(linear_to_srgb(0.001), 0.01292, 1e-15);
  EXPECT_EQ(srgb_to_linear(0.0), 0.0);
  EXPECT_EQ(srgb_to_linear(1.0), 1.0);
  EXPECT_EQ(linear_to_srgb(1.0f), 1.0f);
}

TEST(ColorSpace, ClampsAndMapsNaNToZero) {
  EXPECT_EQ(srgb_to_linear(-0.3), 0.0);
  EXPECT_EQ(srgb_to_linear(7.0), 1.0);
  EXPECT_EQ(linear_to_srgb(-1.0f), 0.0f);
  EXPECT_EQ(linear_to_srgb(2.0), 1.0);
  EXPECT_EQ(srgb_to_linear(std::numeric_limits<double>::quiet_NaN()), 0.0);
  EXPECT_EQ(linear_to_srgb(std::numeric_limits<float>::quiet_NaN()), 0.0f);
}

TEST(ColorSpace, RoundTripsAndIsMonotonic) {
  double previous = -1.0;
  for (int k = 0; k <= 1000; ++k) {
    const double v = k / 1000.0;
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-12) << v;
    const double l = srgb_to_linear(v);
    EXPECT_GT(l, previous) << v;
    previous = l;
  }
}

// Float arguments compute in float: the bits the per-family copies (float pow) gave, so color outputs of
// Biomes, ColorByLayers, KMeansClusters and the island keep their bytes.
TEST(ColorSpace, FloatArgumentsKeepFloatArithmetic) {
  for (int b = 0; b < 256; ++b) {
    const float c = static_cast<float>(b) / 255.0f;
    const float old = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(srgb_to_linear(c)), std::bit_cast<std::uint32_t>(old)) << b;
  }
}

// --- hash.h -----------------------------------------------------------------------------------------------

TEST(Hash, SplitMix64ReferenceValues) {
  // The first outputs of Vigna's splitmix64.c seeded with 0: the state advances by the golden gamma.
  EXPECT_EQ(splitmix64(0), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(splitmix64(kGoldenGamma), 0x6E789E6AA1B965F4ull);
  EXPECT_EQ(mix64(0), 0u) << "the finalizer alone fixes 0";
  EXPECT_EQ(splitmix64(0), mix64(kGoldenGamma));
  EXPECT_NE(mix64(12345), splitmix64(12345)) << "two different functions, two names";
}

TEST(Hash, DeterministicAndDistinct) {
  std::set<std::uint64_t> seen;
  for (std::uint64_t k = 0; k < 100000; ++k) {
    EXPECT_EQ(mix64(k), mix64(k));
    seen.insert(mix64(k));
    seen.insert(splitmix64(k));  // mix64 of k + kGoldenGamma: other arguments, so other outputs
  }
  EXPECT_EQ(seen.size(), 200000u) << "a bijection maps distinct arguments to distinct outputs";
  EXPECT_EQ(hash64(7, 3), hash64(7, 3));
  EXPECT_NE(hash64(7, 3), hash64(7, 4));
  EXPECT_NE(hash64(7, 3), hash64(8, 3));
}

// Strict avalanche: flipping one input bit flips each output bit with probability 1/2.
TEST(Hash, Avalanche) {
  for (auto* f : {+[](std::uint64_t z) { return mix64(z); }, +[](std::uint64_t z) { return splitmix64(z); }}) {
    std::vector<int> flips(64 * 64, 0);
    constexpr int kSamples = 2000;
    for (int s = 0; s < kSamples; ++s) {
      const std::uint64_t x = splitmix64(static_cast<std::uint64_t>(s) * 0x1234567ull + 99);
      const std::uint64_t h = f(x);
      for (int in = 0; in < 64; ++in) {
        const std::uint64_t d = h ^ f(x ^ (1ull << in));
        for (int out = 0; out < 64; ++out) flips[in * 64 + out] += static_cast<int>((d >> out) & 1u);
      }
    }
    double total = 0;
    for (int v : flips) {
      const double p = static_cast<double>(v) / kSamples;
      EXPECT_GT(p, 0.40);
      EXPECT_LT(p, 0.60);
      total += p;
    }
    EXPECT_NEAR(total / flips.size(), 0.5, 0.01);
  }
}

TEST(Hash, UnitDoubleIsInHalfOpenUnitInterval) {
  EXPECT_EQ(unit_double(0), 0.0);
  EXPECT_LT(unit_double(~0ull), 1.0);
  EXPECT_EQ(unit_double(~0ull), 1.0 - 0x1.0p-53);
  double sum = 0;
  for (std::uint64_t k = 0; k < 10000; ++k) {
    const double u = hash01(42, k);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  EXPECT_NEAR(sum / 10000, 0.5, 0.01);
}

// --- text.h -----------------------------------------------------------------------------------------------

TEST(Text, TrimEdgeCases) {
  EXPECT_EQ(trim(""), "");
  EXPECT_EQ(trim("   "), "");
  EXPECT_EQ(trim(" \t\r\n\f\v"), "");
  EXPECT_EQ(trim("a"), "a");
  EXPECT_EQ(trim("  a  "), "a");
  EXPECT_EQ(trim("\t grass: slope < 30 \r\n"), "grass: slope < 30");
  EXPECT_EQ(trim(" a \t b "), "a \t b") << "inner blanks stay";
  EXPECT_EQ(trim("x\n"), "x");
  EXPECT_EQ(trim(std::string_view("  ab  ").substr(1, 3)), "ab") << "views trim like strings";
}

// --- hex_color.h ------------------------------------------------------------------------------------------

TEST(HexColor, ParsesSixDigitsEitherCase) {
  EXPECT_EQ(parse_hex_color("#1b3a6b"), 0x1b3a6bu);
  EXPECT_EQ(parse_hex_color("#1B3A6B"), 0x1b3a6bu);
  EXPECT_EQ(parse_hex_color("#000000"), 0u);
  EXPECT_EQ(parse_hex_color("#ffffff"), 0xffffffu);
}

TEST(HexColor, RefusesAnythingElse) {
  for (const char* bad : {"", "#", "1b3a6b", "#1b3a6", "#1b3a6bb", "#1g3a6b", " #1b3a6b", "#1b3a6b ", "#fff",
                          "#1b3a6bff", "##1b3a6", "#-1b3a6", "#+1b3a6", "0x1b3a6b"})
    EXPECT_FALSE(parse_hex_color(bad).has_value()) << "'" << bad << "'";
}

TEST(HexColor, ToLinear) {
  EXPECT_EQ(hex_to_linear(0xffffff), glm::vec4(1.0f));
  EXPECT_EQ(hex_to_linear(0x000000), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  const glm::vec4 c = hex_to_linear(0x80ff00);
  EXPECT_NEAR(c.r, 0.2158605, 1e-6);  // 128 / 255 through the sRGB curve
  EXPECT_EQ(c.g, 1.0f);
  EXPECT_EQ(c.b, 0.0f);
  EXPECT_EQ(hex_to_srgb(0x336699), glm::vec3(0x33 / 255.0f, 0x66 / 255.0f, 0x99 / 255.0f));
}

// --- categorical_palette.h --------------------------------------------------------------------------------

TEST(CategoricalPalette, TableauFirstThenDistinctHues) {
  EXPECT_EQ(categorical_srgb(0), hex_to_srgb(0x4e79a7));
  EXPECT_EQ(categorical_srgb(11), hex_to_srgb(0x8cd17d));
  std::vector<glm::vec3> colors;
  for (long id = 0; id < 64; ++id) colors.push_back(categorical_srgb(id));
  for (std::size_t a = 0; a < colors.size(); ++a)
    for (std::size_t b = a + 1; b < colors.size(); ++b)
      EXPECT_GT(glm::length(colors[a] - colors[b]), 1e-3f) << a << " and " << b << " look the same";
  EXPECT_EQ(categorical_srgb(-1), glm::vec3(kNoClassGray));
  EXPECT_EQ(categorical_srgb(-7), categorical_srgb(-1));
  for (long id : {0L, 5L, 12L, 40L}) {
    const glm::vec3 s = categorical_srgb(id);
    EXPECT_EQ(categorical_linear(id), glm::vec4(srgb_to_linear(s.r), srgb_to_linear(s.g), srgb_to_linear(s.b), 1.0f));
  }
}

// --- cancellable_rows.h -----------------------------------------------------------------------------------

ExecContext context_of(const CancelToken* cancel) {
  const NodeType* t = NodeRegistry::instance().find("Add");
  std::vector<ParamValue> params;
  for (const auto& p : t->params) params.push_back(p.default_value);
  ExecContext ctx(*t, "rows", Domain{}, std::vector<PortValue>(t->inputs.size()), std::move(params));
  ctx.set_cancel_token(cancel);
  return ctx;
}

TEST(CancellableRows, EveryRowOnceAndProgressInItsSpan) {
  CancelToken token;
  ExecContext ctx = context_of(&token);
  std::mutex m;
  std::vector<double> reported;
  ctx.set_progress_callback([&](double f) {
    std::lock_guard lock(m);
    reported.push_back(f);
  });
  std::vector<std::atomic<int>> hits(1000);
  parallel_rows(
      ctx, 1000, [&](int j) { hits[static_cast<std::size_t>(j)]++; }, 0.25, 0.75);
  for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
  ASSERT_FALSE(reported.empty());
  for (double f : reported) {
    EXPECT_GE(f, 0.25);
    EXPECT_LE(f, 0.75);
  }
  EXPECT_DOUBLE_EQ(*std::max_element(reported.begin(), reported.end()), 0.75);

  reported.clear();
  for_each_row_unreported(&ctx, 1000, [&](int j) { hits[static_cast<std::size_t>(j)]++; });
  EXPECT_TRUE(reported.empty()) << "a loop inside a reporting iteration says nothing";
  for (const auto& h : hits) EXPECT_EQ(h.load(), 2);

  int plain = 0;
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  for_each_row(nullptr, 50, [&](int) { ++plain; });  // a library call without a context
  EXPECT_EQ(plain, 50);
}

TEST(CancellableRows, StopsWhenCancelled) {
  for (int variant = 0; variant < 3; ++variant) {
    CancelToken token;
    ExecContext ctx = context_of(&token);
    std::atomic<int> done{0};
    auto row = [&](int) {
      if (++done == 20) token.cancel();
    };
    if (variant == 0) {
      EXPECT_THROW(parallel_rows(ctx, 100000, row), Cancelled);
    } else if (variant == 1) {
      EXPECT_THROW(for_each_row(&ctx, 100000, row), Cancelled);
    } else {
      EXPECT_THROW(for_each_row_unreported(&ctx, 100000, row), Cancelled);
    }
    EXPECT_LT(done.load(), 100000) << "rows kept running after the cancel (variant " << variant << ")";
  }
}

// --- report_builder.h -------------------------------------------------------------------------------------

TEST(ReportBuilder, OrderedIndentedAndNullForNonFinite) {
  ReportJson j;
  j["zeta"] = 1;
  j["alpha"] = report_number(0.5);
  j["nan"] = report_number(std::numeric_limits<double>::quiet_NaN());
  j["inf"] = report_number(-std::numeric_limits<double>::infinity());
  const auto report = make_report(j);
  EXPECT_EQ(report->json, "{\n  \"zeta\": 1,\n  \"alpha\": 0.5,\n  \"nan\": null,\n  \"inf\": null\n}");
  const auto parsed = nlohmann::json::parse(report->json);
  EXPECT_TRUE(parsed["nan"].is_null());
  EXPECT_EQ(report_text(j), report->json);
  EXPECT_DOUBLE_EQ(report_number(1e300).get<double>(), 1e300);
  EXPECT_EQ(make_report(report_text(j))->json, report->json) << "text and object give the same report";
}

// --- smoothstep.h ----------------------------------------------------------------------------------------
TEST(Smoothstep, HermiteCurveClampedToTheUnitInterval) {
  EXPECT_EQ(smoothstep01(-3.0), 0.0);
  EXPECT_EQ(smoothstep01(0.0), 0.0);
  EXPECT_EQ(smoothstep01(0.5), 0.5);
  EXPECT_EQ(smoothstep01(1.0), 1.0);
  EXPECT_EQ(smoothstep01(7.0), 1.0);
  EXPECT_DOUBLE_EQ(smoothstep01(0.25), 0.15625);  // 0.25^2 * 2.5
  EXPECT_DOUBLE_EQ(smoothstep01(0.25) + smoothstep01(0.75), 1.0) << "point-symmetric about (0.5, 0.5)";
  // Zero slope at both ends (C1): the difference quotient vanishes as h^2.
  const double h = 1e-4;
  EXPECT_LT(smoothstep01(h) / h, 1e-3);
  EXPECT_LT((1.0 - smoothstep01(1.0 - h)) / h, 1e-3);
  EXPECT_TRUE(std::isnan(smoothstep01(std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace orogen
