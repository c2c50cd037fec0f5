#include "nodes/climate/resources.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/climate/sun.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/field/slope.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::climate {

double monthly_base_temperature(double t_december, double t_june, int month) {
  return t_december + ((6.0 - std::abs(6 - month)) / 6.0) * (t_june - t_december);
}

namespace {

std::shared_ptr<Image> monthly_image(const Domain& d, const std::string& prefix = "") {
  auto img = std::make_shared<Image>(d, 12);
  for (const char* m : kMonthNames) img->channel_names.push_back(prefix + m);
  return img;
}

// Channel of `img` for month m (1..12): 12 channels by month, or 1 channel for all.
int month_channel(const Image& img, int m) { return img.channels == 12 ? m - 1 : 0; }

void check_monthly(const Image* img, const Domain& d, const char* what) {
  if (!img) return;
  require_same_grid(img->domain, d, what);
  if (img->channels != 12 && img->channels != 1)
    throw NodeError(std::string(what) + ": expected 12 monthly channels or 1, got " + std::to_string(img->channels));
}

void check_field(const Heightfield* f, const Domain& d, const char* what) {
  if (f) require_same_grid(f->domain, d, what);
}

double finite_or(double v, double fallback) { return std::isfinite(v) ? v : fallback; }

}  // namespace

TemperatureResult temperature(const Heightfield& z, const TemperatureParams& p, const Image* lit_hours,
                              const ExecContext* ctx) {
  check_monthly(lit_hours, z.domain, "illumination");
  TemperatureResult out{monthly_image(z.domain), std::make_shared<Heightfield>(z.domain)};
  double base[12];
  for (int m = 1; m <= 12; ++m) base[m - 1] = monthly_base_temperature(p.t_december, p.t_june, m);
  const double lapse = p.lapse_rate / 1000.0;
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      const double alt = -lapse * (static_cast<double>(z.at(i, j)) - p.reference_altitude);
      float* px = out.monthly->pixel(i, j);
      double sum = 0.0;
      for (int m = 1; m <= 12; ++m) {
        double t = base[m - 1] + alt;
        if (lit_hours)
          t += p.illumination_gain * (lit_hours->pixel(i, j)[month_channel(*lit_hours, m)] - p.reference_hours);
        px[m - 1] = static_cast<float>(t);
        sum += t;
      }
      out.mean->at(i, j) = static_cast<float>(sum / 12.0);
    }
  });
  return out;
}

SoilHumidityParams SoilHumidityParams::defaults() {
  SoilHumidityParams p;
  const double rain[12] = {80, 70, 60, 50, 40, 25, 15, 20, 40, 60, 80, 90};
  for (int m = 1; m <= 12; ++m) p.rainfall.points.push_back({static_cast<double>(m), rain[m - 1]});
  p.intensity.points = {{1.0, 10.0}, {12.0, 10.0}};
  return p;
}

SoilHumidityResult soil_humidity(const Heightfield& z, const SoilHumidityParams& p, const Heightfield* infiltration,
                                 const Heightfield* wetness, const Heightfield* water, const ExecContext* ctx) {
  check_field(infiltration, z.domain, "infiltration");
  check_field(wetness, z.domain, "wetness");
  check_field(water, z.domain, "water");
  double rain[12], intensity[12];
  for (int m = 1; m <= 12; ++m) {
    rain[m - 1] = std::max(0.0, finite_or(p.rainfall.evaluate(m), 0.0));
    intensity[m - 1] = std::max(0.0, finite_or(p.intensity.evaluate(m), 0.0));
  }
  SoilHumidityResult out{monthly_image(z.domain), monthly_image(z.domain), std::make_shared<Heightfield>(z.domain)};
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double rate = infiltration ? finite_or(infiltration->at(i, j), 0.0) : p.infiltration;
      rate = std::max(0.0, rate);
      if (z.width() > 1 || z.height() > 1) {
        double gp = 0.0, gq = 0.0;
        gradient_at(z, i, j, gp, gq);
        if (slope_degrees(gp, gq) > p.max_slope) rate = 0.0;
      }
      double w = wetness ? std::clamp(finite_or(wetness->at(i, j), 0.0), 0.0, 1.0) : 0.0;
      if (water && water->at(i, j) > p.water_threshold) w = 1.0;
      double s[12];
      for (int m = 0; m < 12; ++m) {
        const double f = intensity[m] > 0.0 ? std::min(1.0, rate / intensity[m]) : 1.0;
        s[m] = std::min(rain[m], rain[m] * (f + w * (1.0 - f)));
      }
      float* mo = out.monthly->pixel(i, j);
      float* we = out.weighted->pixel(i, j);
      double annual = 0.0;
      for (int m = 0; m < 12; ++m) {
        const double v = kHumidityWeights[0] * s[m] + kHumidityWeights[1] * s[(m + 11) % 12] +
                         kHumidityWeights[2] * s[(m + 10) % 12];
        mo[m] = static_cast<float>(s[m]);
        we[m] = static_cast<float>(v);
        annual += v;
      }
      out.annual->at(i, j) = static_cast<float>(annual);
    }
  });
  return out;
}

std::shared_ptr<Image> resource_stack(const Heightfield& z, const Image* temperature, const Image* illumination,
                                      const Image* humidity, const ExecContext* ctx) {
  struct Group {
    const Image* img;
    std::string name;
  };
  std::vector<Group> groups;
  for (const Group& g :
       {Group{temperature, "temperature"}, Group{illumination, "illumination"}, Group{humidity, "humidity"}}) {
    if (!g.img) continue;
    require_same_grid(g.img->domain, z.domain, g.name);
    groups.push_back(g);
  }
  int channels = 1;
  for (const auto& g : groups) channels += g.img->channels;
  auto out = std::make_shared<Image>(z.domain, channels);
  out->channel_names.push_back("slope");
  for (const auto& g : groups)
    for (int c = 0; c < g.img->channels; ++c)
      out->channel_names.push_back(g.name + "_" +
                                   (static_cast<std::size_t>(c) < g.img->channel_names.size()
                                        ? g.img->channel_names[static_cast<std::size_t>(c)]
                                        : std::to_string(c)));
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      float* px = out->pixel(i, j);
      double gp = 0.0, gq = 0.0;
      if (z.width() > 1 || z.height() > 1) gradient_at(z, i, j, gp, gq);
      px[0] = static_cast<float>(slope_degrees(gp, gq));
      int k = 1;
      for (const auto& g : groups) {
        const float* src = g.img->pixel(i, j);
        for (int c = 0; c < g.img->channels; ++c) px[k++] = src[c];
      }
    }
  });
  return out;
}

namespace {
CurveValue monthly_curve_default(bool rain) {
  const auto p = SoilHumidityParams::defaults();
  return rain ? p.rainfall : p.intensity;
}
}  // namespace

OROGEN_NODE(Temperature) {
  b.reach_pointwise();
  b.category("climate").description(
      "Monthly air temperature: the seasonal curve T(m) = T_dec + (6 - |6 - m|)/6 (T_jun - T_dec) between a "
      "December and a June temperature at the reference altitude (H. Long (2016), Using procedural methods to "
      "generate realistic virtual rural worlds, eq. 3.4), minus the lapse rate times the altitude above the "
      "reference (the standard atmosphere's 6.5 C/km; Long uses 6.4), plus an optional term for the lit hours "
      "of SunIllumination. Months 1..12 are January..December; for the southern hemisphere swap the two "
      "temperatures.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("illumination", PortType::Image)
      .optional()
      .description("Lit hours per day (SunIllumination.out): 12 monthly channels or 1");
  b.output("out", PortType::Image).description("Temperature, deg C, 12 channels jan..dec");
  b.output("mean", PortType::Heightfield).description("Annual mean temperature, deg C").kind(OutputKind::Signed);
  b.param_float("t_december", 5.0)
      .range(-80.0, 60.0)
      .unit(Unit::DegreeCelsius)
      .description("December temperature at the reference altitude, deg C, -80..60");
  b.param_float("t_june", 22.0)
      .range(-80.0, 60.0)
      .unit(Unit::DegreeCelsius)
      .description("June temperature at the reference altitude, deg C, -80..60");
  b.param_float("lapse_rate", 6.4)
      .range(0.0, 15.0)
      .unit(Unit::DegreeCelsiusPerKilometre)
      .description("Temperature drop per km of altitude, deg C/km, 0..15");
  b.param_float("reference_altitude", 0.0)
      .range(-1e4, 1e4)
      .soft_range(-500, 3000)
      .unit(Unit::Metre)
      .description("Altitude of t_december and t_june, metres");
  b.param_float("illumination_gain", 0.0)
      .range(-5.0, 5.0)
      .unit(Unit::DegreeCelsiusPerHour)
      .description("Warming per lit hour above reference_hours, deg C/h, -5..5 (used when illumination is connected)");
  b.param_float("reference_hours", 12.0)
      .range(0.0, 24.0)
      .unit(Unit::Hour)
      .description("Lit hours per day that add no warming, hours 0..24");
  // Working memory beyond the outputs, 32 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 32); });
  b.execute([](ExecContext& ctx) {
    TemperatureParams p;
    p.t_december = ctx.param<double>("t_december");
    p.t_june = ctx.param<double>("t_june");
    p.lapse_rate = ctx.param<double>("lapse_rate");
    p.reference_altitude = ctx.param<double>("reference_altitude");
    p.illumination_gain = ctx.param<double>("illumination_gain");
    p.reference_hours = ctx.param<double>("reference_hours");
    const auto in = ctx.require<Heightfield>("in");
    const auto lit = secondary_input<Image>(ctx, "illumination", in->domain);
    auto r = temperature(*in, p, lit.get(), &ctx);
    ctx.set_output("out", r.monthly);
    ctx.set_output("mean", r.mean);
  });
}

OROGEN_NODE(SoilHumidity) {
  b.reach_local(0.0, 1);  // slope by central differences
  b.category("climate").description(
      "Monthly soil humidity, the rain the soil absorbs: S = R x min(1, infiltration / intensity) (H. Long "
      "(2016), Using procedural methods to generate realistic virtual rural worlds, eq. 3.5, clamped so it "
      "never exceeds the rainfall R), no infiltration above max_slope (cliffs), raised toward R by a wetness "
      "mask (e.g. FlowAccumulation.flow) and saturated under standing water (WaterFlow.out, Lakes.depth); "
      "then Long's weighted history S_wh(m) = S(m)/2 + S(m-1)/3 + S(m-2)/6 (eq. 3.6, wrapping around the "
      "year). Soil infiltration rates: sand > 30, loam 10-20, clay 1-5 mm/h (FAO).");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("infiltration", PortType::Heightfield)
      .optional()
      .description("Soil infiltration rate, mm/h (replaces the infiltration parameter)");
  b.input("wetness", PortType::Heightfield)
      .optional()
      .description("Wetness mask in 0..1: the share of the rain that cannot run off is raised toward 1");
  b.input("water_depth", PortType::Heightfield)
      .unit(Unit::Metre)
      .optional()
      .description("Standing water depth, metres; deeper than saturation_depth saturates the soil");
  b.output("out", PortType::Image).description("Weighted soil humidity S_wh, mm, 12 channels jan..dec");
  b.output("monthly", PortType::Image).description("Soil humidity S of each month alone, mm, 12 channels");
  b.output("annual", PortType::Heightfield).description("Sum of S_wh over the year, mm").kind(OutputKind::Scalar);
  b.param_curve("rainfall", monthly_curve_default(true))
      .unit(Unit::Millimetre)
      .description("Rainfall per month, mm (x: month 1..12, y: mm >= 0)");
  b.param_curve("rainfall_rate", monthly_curve_default(false))
      .unit(Unit::MillimetrePerHour)
      .description("Average rainfall intensity per month, mm/h (x: month 1..12, y: mm/h > 0)");
  b.param_float("infiltration", 5.0)
      .range(0.0, 200.0)
      .unit(Unit::MillimetrePerHour)
      .description("Soil infiltration rate, mm/h, 0..200, when no field is connected");
  b.param_float("max_slope", 30.0)
      .range(0.0, 90.0)
      .unit(Unit::Degree)
      .description("Slope above which nothing infiltrates, degrees 0..90 (90: none)");
  b.param_float("saturation_depth", 0.01)
      .range(0.0, 100.0)
      .unit(Unit::Metre)
      .description("Water depth above which the soil is saturated, metres");
  // Working memory beyond the outputs, 64 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 64); });
  b.execute([](ExecContext& ctx) {
    SoilHumidityParams p;
    p.rainfall = ctx.param<CurveValue>("rainfall");
    p.intensity = ctx.param<CurveValue>("rainfall_rate");
    p.infiltration = ctx.param<double>("infiltration");
    p.max_slope = ctx.param<double>("max_slope");
    p.water_threshold = ctx.param<double>("saturation_depth");
    const auto in = ctx.require<Heightfield>("in");
    const auto inf = secondary_input<Heightfield>(ctx, "infiltration", in->domain);
    const auto wet = secondary_input<Heightfield>(ctx, "wetness", in->domain);
    const auto water = secondary_input<Heightfield>(ctx, "water_depth", in->domain);
    auto r = soil_humidity(*in, p, inf.get(), wet.get(), water.get(), &ctx);
    ctx.set_output("out", r.weighted);
    ctx.set_output("monthly", r.monthly);
    ctx.set_output("annual", r.annual);
  });
}

OROGEN_NODE(ResourceStack) {
  b.reach_local(0.0, 1);  // slope by central differences
  b.category("climate").description(
      "Collects the resources of a cell into one multi-channel image for KMeansClusters, as H. Long (2016), "
      "Using procedural methods to generate realistic virtual rural worlds (table 4.1): slope (degrees), then "
      "the channels of each connected image prefixed with its group: temperature_jan.., illumination_jan.., "
      "humidity_jan...");
  b.input("in", PortType::Heightfield).description("Height, metres (for the slope)");
  b.input("temperature", PortType::Image)
      .unit(Unit::DegreeCelsius)
      .optional()
      .description("Monthly temperature, deg C (Temperature.out)");
  b.input("illumination", PortType::Image).optional().description("Monthly lit hours (SunIllumination.out)");
  b.input("humidity", PortType::Image).optional().description("Monthly soil humidity, mm (SoilHumidity.out)");
  b.output("out", PortType::Image).description("slope, temperature_*, illumination_*, humidity_* channels");
  // One channel of slope and every channel of each connected image (twelve months each before they are known),
  // against the four channels the default estimate counts for an image.
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    std::uint64_t channels = 1;
    for (const char* group : {"temperature", "illumination", "humidity"}) {
      if (const PortValue* v = q.input(group))
        channels += static_cast<std::uint64_t>(std::get<ImagePtr>(*v)->channels);
      else if (!q.inputs && q.is_linked(group))
        channels += 12;
    }
    const std::uint64_t samples = static_cast<std::uint64_t>(q.domain.resolution.x) * q.domain.resolution.y;
    return channels > 4 ? samples * (channels - 4) * sizeof(float) : 0;
  });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto t = secondary_input<Image>(ctx, "temperature", in->domain);
    const auto l = secondary_input<Image>(ctx, "illumination", in->domain);
    const auto h = secondary_input<Image>(ctx, "humidity", in->domain);
    ctx.set_output("out", resource_stack(*in, t.get(), l.get(), h.get(), &ctx));
  });
}

}  // namespace orogen::climate
