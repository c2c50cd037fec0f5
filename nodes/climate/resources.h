#pragma once
// Per-cell resources for ecosystems after H. Long (2016), Using procedural methods to generate realistic
// virtual rural worlds (section 3.2): monthly temperature with the altitude lapse rate, monthly soil
// humidity with its weighted history, and the resource stack clustered by KMeansClusters.
// Months are 1..12 (January..December); monthly images have 12 channels named jan..dec.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/param_value.h"

namespace orogen::climate {

// Long's eq. 3.4: T(m) = T_dec + (6 - |6 - m|) / 6 * (T_jun - T_dec), degrees Celsius at the reference
// altitude; symmetric about June (T(6 - k) = T(6 + k)), T(12) = T_dec, T(6) = T_jun.
double monthly_base_temperature(double t_december, double t_june, int month);

struct TemperatureParams {
  double t_december = 5.0;          // deg C at the reference altitude in December
  double t_june = 22.0;             // deg C at the reference altitude in June
  double lapse_rate = 6.4;          // deg C per km of altitude above the reference
  double reference_altitude = 0.0;  // m
  double illumination_gain = 0.0;   // deg C per lit hour above reference_hours (optional sun term)
  double reference_hours = 12.0;    // h
};

struct TemperatureResult {
  std::shared_ptr<Image> monthly;     // 12 channels, deg C
  std::shared_ptr<Heightfield> mean;  // annual mean, deg C
};
// T(x, m) = T_base(m) - lapse_rate / 1000 * (z - reference_altitude) + gain * (hours(m) - reference_hours).
// `lit_hours` (optional) holds 12 monthly channels or 1 channel used for every month.
TemperatureResult temperature(const Heightfield& z, const TemperatureParams& p, const Image* lit_hours = nullptr,
                              const ExecContext* ctx = nullptr);

struct SoilHumidityParams {
  CurveValue rainfall;            // mm per month, by month 1..12
  CurveValue intensity;           // mm/h, average rainfall intensity by month 1..12
  double infiltration = 5.0;      // mm/h, soil infiltration rate (when no field is given)
  double max_slope = 30.0;        // degrees; infiltration is 0 on steeper ground
  double water_threshold = 0.01;  // m; standing water deeper than this saturates the soil
  static SoilHumidityParams defaults();
};

// Weights of the history S_wh(m) = 1/2 S(m) + 1/3 S(m-1) + 1/6 S(m-2) (months wrap around the year).
inline constexpr double kHumidityWeights[3] = {1.0 / 2.0, 1.0 / 3.0, 1.0 / 6.0};

struct SoilHumidityResult {
  std::shared_ptr<Image> weighted;      // S_wh, mm, 12 channels
  std::shared_ptr<Image> monthly;       // S, mm, 12 channels
  std::shared_ptr<Heightfield> annual;  // sum of S over the year, mm
};
// S(m) = R(m) * (f + w (1 - f)), f = min(1, infiltration / intensity(m)) (Long's eq. 3.5 clamped to the
// rainfall), w = wetness in [0, 1] (1 where standing water is deeper than water_threshold). Never exceeds
// the month's rainfall.
SoilHumidityResult soil_humidity(const Heightfield& z, const SoilHumidityParams& p, const Heightfield* infiltration,
                                 const Heightfield* wetness, const Heightfield* water,
                                 const ExecContext* ctx = nullptr);

// One image: "slope" (degrees) then "temperature_jan".., "illumination_jan".., "humidity_jan".. for the
// given images (each channel name is prefixed with the group name; null images are left out).
std::shared_ptr<Image> resource_stack(const Heightfield& z, const Image* temperature, const Image* illumination,
                                      const Image* humidity, const ExecContext* ctx = nullptr);

}  // namespace orogen::climate
