#include "nodes/hydrology/drainage_metrics.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/report_builder.h"
#include "nodes/hydrology/channels.h"

namespace orogen::hydrology {
namespace {

// Ordinary least squares y = a + b x with R^2.
LogFit line_fit(const std::vector<double>& x, const std::vector<double>& y) {
  LogFit f;
  f.points = static_cast<int>(x.size());
  if (x.size() < 2) return f;
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
    syy += (y[k] - my) * (y[k] - my);
  }
  if (!(sxx > 0)) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  return f;
}

}  // namespace

LogFit binned_log_fit(std::span<const double> x, std::span<const double> y, double bin_width, int min_count) {
  std::map<long, std::pair<double, double>> sum;  // bin -> (sum log x, sum log y)
  std::map<long, int> count;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!(x[k] > 0) || !(y[k] > 0)) continue;
    const double lx = std::log10(x[k]), ly = std::log10(y[k]);
    const long b = static_cast<long>(std::floor(lx / bin_width));
    sum[b].first += lx;
    sum[b].second += ly;
    ++count[b];
  }
  std::vector<double> bx, by;
  for (const auto& [b, s] : sum)
    if (count[b] >= min_count) {
      bx.push_back(s.first / count[b]);
      by.push_back(s.second / count[b]);
    }
  return line_fit(bx, by);
}

NetworkMetrics network_metrics(const FlowGrid& g, const D8Flow& f, std::span<const std::int32_t> stack,
                               std::span<const std::uint8_t> channel, std::span<const double> area,
                               std::span<const float> z, std::span<const std::uint8_t> exclude_slope) {
  NetworkSamples s;
  std::vector<std::int32_t> order = strahler_orders(g, f, stack, channel);
  // Horton streams: maximal runs of one order. A stream starts at a channel cell none of whose channel
  // donors has its order; it continues through the (unique) donor of the same order.
  std::vector<std::int32_t> stream(g.size(), -1);
  std::vector<double> longest(g.size(), 0.0);  // main-stream length: longest flow path from the divide
  for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
    const std::int32_t c = *it;
    double best = 0.0;
    std::int32_t same = -1;
    for (unsigned mask = f.donors[c]; mask; mask &= mask - 1) {
      const int k = std::countr_zero(mask);
      const std::int32_t d = c + g.offset(k);
      best = std::max(best, longest[d] + g.distance(opposite(k)));
      if (channel[c] && channel[d] && order[d] == order[c]) same = d;
    }
    longest[c] = best;
    if (!channel[c]) continue;
    const bool drains = f.receiver[c] != c;
    ChannelSample cell{same, order[c], drains ? g.distance(f.direction[c]) : 0.0, area[c], best, std::nullopt};
    if (drains && (exclude_slope.empty() || !exclude_slope[c]))
      cell.slope = (static_cast<double>(z[c]) - z[f.receiver[c]]) / g.distance(f.direction[c]);
    add_channel_sample(s, stream, static_cast<std::size_t>(c), cell);
  }
  NetworkMetrics m = network_figures(s, g.size());
  m.order = std::move(order);
  return m;
}

void add_channel_sample(NetworkSamples& s, std::span<std::int32_t> stream, std::size_t c, const ChannelSample& cell) {
  ++s.channel_cells;
  if (cell.same >= 0) {
    stream[c] = stream[static_cast<std::size_t>(cell.same)];
  } else {
    stream[c] = static_cast<std::int32_t>(s.stream_order.size());
    s.stream_order.push_back(cell.order);
    s.stream_length.push_back(0.0);
  }
  if (cell.step > 0.0) s.stream_length[static_cast<std::size_t>(stream[c])] += cell.step;
  s.area.push_back(cell.area);
  s.main_length.push_back(cell.main_length);
  if (cell.slope) {
    s.slope_area.push_back(cell.area);
    s.slope.push_back(*cell.slope);
  }
}

NetworkMetrics network_figures(const NetworkSamples& s, std::size_t cells) {
  NetworkMetrics m;
  m.cells = cells;
  m.channel_cells = s.channel_cells;
  for (int o : s.stream_order) m.max_order = std::max(m.max_order, o);
  m.stream_counts.assign(static_cast<std::size_t>(m.max_order), 0);
  m.mean_stream_length.assign(static_cast<std::size_t>(m.max_order), 0.0);
  for (std::size_t k = 0; k < s.stream_order.size(); ++k) {
    ++m.stream_counts[static_cast<std::size_t>(s.stream_order[k] - 1)];
    m.mean_stream_length[static_cast<std::size_t>(s.stream_order[k] - 1)] += s.stream_length[k];
  }
  std::vector<double> w, ln, ll;
  std::vector<double> wl;
  for (int o = 1; o <= m.max_order; ++o) {
    const std::size_t k = static_cast<std::size_t>(o - 1);
    if (m.stream_counts[k]) m.mean_stream_length[k] /= m.stream_counts[k];
    w.push_back(o);
    ln.push_back(std::log10(m.stream_counts[k]));
    if (m.mean_stream_length[k] > 0) {
      wl.push_back(o);
      ll.push_back(std::log10(m.mean_stream_length[k]));
    }
  }
  if (w.size() >= 2) m.bifurcation_ratio = std::pow(10.0, -line_fit(w, ln).slope);
  if (wl.size() >= 2) m.length_ratio = std::pow(10.0, line_fit(wl, ll).slope);
  m.hack = binned_log_fit(s.area, s.main_length);
  m.flint = binned_log_fit(s.slope_area, s.slope);
  return m;
}

std::string DrainageReport::json() const {
  const NetworkMetrics& n = network;
  ReportJson j;
  j["cells"] = n.cells;
  j["pits_per_million_cells"] = pits_per_million;
  j["pits_outside_lakes_per_million_cells"] = pits_outside_lakes_per_million;
  j["depressions"] = depressions;
  j["lakes"] = lakes;
  j["lake_cells_fraction"] = lake_cells_fraction;
  j["lake_min_depth_m"] = lake.depth;
  j["lake_min_area_m2"] = lake.area;
  j["channel_threshold_m2"] = threshold;
  j["channel_cells"] = n.channel_cells;
  j["max_strahler_order"] = n.max_order;
  j["stream_counts"] = n.stream_counts;
  ReportJson lengths = ReportJson::array();
  for (double l : n.mean_stream_length) lengths.push_back(report_number(l));
  j["mean_stream_length_m"] = lengths;
  j["bifurcation_ratio"] = report_number(n.bifurcation_ratio);
  j["length_ratio"] = report_number(n.length_ratio);
  j["hack_exponent"] = report_number(n.hack.slope);
  j["hack_r2"] = report_number(n.hack.r2);
  j["concavity_theta"] = report_number(-n.flint.slope);
  j["concavity_r2"] = report_number(n.flint.r2);
  j["steepness_ks"] = report_number(std::isfinite(n.flint.intercept) ? std::pow(10.0, n.flint.intercept) : NAN);
  j["slope_area_bins"] = n.flint.points;
  return report_text(j);
}

DrainageReport drainage_metrics(const Heightfield& in, double threshold, const ExecContext* ctx,
                                const LakeThreshold& lake_threshold) {
  const FlowGrid g = FlowGrid::of(in.domain);
  DrainageReport r;
  r.threshold = threshold;
  r.lake = lake_threshold;
  std::vector<float> z = in.data, spill(g.size());
  fill_depressions(g, z, FlatMode::Epsilon, {}, ctx, spill);
  std::vector<std::uint8_t> lake(g.size());
  for (std::size_t c = 0; c < g.size(); ++c) lake[c] = spill[c] > in.data[c];
  // Depressions: 8-connected components of raised cells. A component is a lake when it is deep and large
  // enough; its cells keep lake = 2, the others lake = 1 (still left out of Flint's fit: their filled
  // slopes are the epsilon of the fill, not the terrain's).
  {
    const double cell_area = in.domain.spacing.x * in.domain.spacing.y;
    std::vector<std::int32_t> label(g.size(), -1), members;
    for (std::size_t s = 0; s < g.size(); ++s) {
      if (!lake[s] || label[s] >= 0) continue;
      members.clear();
      members.push_back(static_cast<std::int32_t>(s));
      label[s] = static_cast<std::int32_t>(r.depressions);
      double depth = 0.0;
      for (std::size_t k = 0; k < members.size(); ++k) {
        const std::int32_t c = members[k];
        depth = std::max(depth, static_cast<double>(spill[c]) - in.data[c]);
        const int ci = c % g.nx, cj = c / g.nx;
        for (int n = 0; n < 8; ++n) {
          const int i = ci + kDi[n], j = cj + kDj[n];
          if (i < 0 || j < 0 || i >= g.nx || j >= g.ny) continue;
          const std::int32_t d = g.index(i, j);
          if (lake[d] && label[d] < 0) {
            label[d] = label[s];
            members.push_back(d);
          }
        }
      }
      ++r.depressions;
      const bool is_lake =
          depth >= lake_threshold.depth && static_cast<double>(members.size()) * cell_area >= lake_threshold.area;
      if (is_lake) {
        ++r.lakes;
        for (std::int32_t c : members) lake[c] = 2;
      }
    }
  }
  std::size_t pits = 0, pits_outside = 0, lake_cells = 0;
  for (std::size_t c = 0; c < g.size(); ++c) lake_cells += lake[c] == 2;
  for (int j = 1; j < g.ny - 1; ++j)
    for (int i = 1; i < g.nx - 1; ++i) {
      const std::int32_t c = g.index(i, j);
      bool lower = false;
      for (int k = 0; k < 8 && !lower; ++k) lower = in.data[c + g.offset(k)] < in.data[c];
      pits += !lower;
      pits_outside += !lower && lake[c] != 2;
    }
  const double per = 1e6 / static_cast<double>(std::max<std::size_t>(1, g.size()));
  r.pits_per_million = static_cast<double>(pits) * per;
  r.pits_outside_lakes_per_million = static_cast<double>(pits_outside) * per;
  r.lake_cells_fraction = static_cast<double>(lake_cells) / static_cast<double>(std::max<std::size_t>(1, g.size()));
  const D8Flow f = d8_flow(g, z, {}, ctx);
  const auto stack = stack_order(g, f);
  // Whole cells times the cell area, as FlowAccumulation's D8 area: exact in any order, so across tiles too.
  const auto area = d8_area(g, f, ctx);
  std::vector<std::uint8_t> channel(g.size());
  for (std::size_t c = 0; c < g.size(); ++c) channel[c] = area[c] >= threshold;
  r.network = network_metrics(g, f, stack, channel, area, z, lake);
  return r;
}

OROGEN_NODE(DrainageMetrics) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Realism figures of a terrain's drainage, to compare with real basins: undrained pits per million cells, "
          "in all and outside lakes (a lake is a depression of the Priority-Flood fill at least lake_depth deep and "
          "lake_area large; smaller ones are artifacts and their pits count); "
          "the Strahler order map (Strahler 1957) of the channels (D8 contributing area >= threshold on the "
          "Priority-Flood+epsilon filled terrain); Horton's bifurcation and length ratios (Horton 1945; real networks "
          "3-5 and 1.5-3.5); Hack's exponent h of main-stream length L ~ A^h (Hack 1957; 0.5-0.6); and the concavity "
          "theta of Flint's slope-area law S = ks A^-theta (Flint 1974; 0.35-0.6) with the R^2 of its fit on "
          "log-binned means (0.1 decade bins). The figures are a JSON report (orogen eval --stats lists it).");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield)
      .description("Strahler order of channel cells, 0 elsewhere")
      .kind(OutputKind::Scalar);
  b.output("report", PortType::Report).description("The figures as a JSON object");
  b.param_float("threshold", 1e5)
      .range(1.0, 1e14)
      .soft_range(1e3, 1e8)
      .unit(Unit::SquareMetre)
      .description("Contributing area at which a channel starts");
  b.param_float("lake_depth", 2.0)
      .range(0.0, 1e4)
      .soft_range(0.0, 50.0)
      .unit(Unit::Metre)
      .description("Depth (spill level minus lowest cell) from which a depression counts as a lake");
  b.param_float("lake_area", 40000.0)
      .range(0.0, 1e12)
      .soft_range(0.0, 1e7)
      .unit(Unit::SquareMetre)
      .description("Area from which a depression counts as a lake");
  // Working memory beyond the outputs, 32 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 32); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    LakeThreshold lake;
    lake.depth = ctx.param<double>("lake_depth");
    lake.area = ctx.param<double>("lake_area");
    DrainageReport r = drainage_metrics(*in, ctx.param<double>("threshold"), &ctx, lake);
    auto order = std::make_shared<Heightfield>(in->domain);
    for (std::size_t c = 0; c < order->data.size(); ++c) order->data[c] = static_cast<float>(r.network.order[c]);
    ctx.set_output("out", order);
    ctx.set_output("report", make_report(r.json()));
  });
}

}  // namespace orogen::hydrology
