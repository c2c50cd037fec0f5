#include "graph/units.h"

#include <stdexcept>

namespace orogen {

const std::vector<UnitInfo>& all_units() {
  static const std::vector<UnitInfo> table = {
      {Unit::None, "none", "", "no unit"},
      {Unit::Unitless, "unitless", "", "unitless"},
      {Unit::Factor, "factor", "x", "times"},
      {Unit::Count, "count", "count", "count"},
      {Unit::Id, "id", "id", "identifier"},
      {Unit::InputUnits, "input", "input units", "the input's units"},
      {Unit::Metre, "m", "m", "metres"},
      {Unit::SquareMetre, "m2", "m²", "square metres"},
      {Unit::CubicMetre, "m3", "m³", "cubic metres"},
      {Unit::PerMetre, "per_m", "1/m", "per metre"},
      {Unit::MetrePerMetre, "m_per_m", "m/m", "metres per metre (rise over run)"},
      {Unit::Millimetre, "mm", "mm", "millimetres"},
      {Unit::MillimetrePerHour, "mm_per_h", "mm/h", "millimetres per hour"},
      {Unit::Degree, "deg", "°", "degrees"},
      {Unit::DegreeCelsius, "degC", "°C", "degrees Celsius"},
      {Unit::DegreeCelsiusPerKilometre, "degC_per_km", "°C/km", "degrees Celsius per kilometre"},
      {Unit::DegreeCelsiusPerHour, "degC_per_h", "°C/h", "degrees Celsius per hour"},
      {Unit::Millisecond, "ms", "ms", "milliseconds"},
      {Unit::Second, "s", "s", "seconds"},
      {Unit::Hour, "h", "h", "hours"},
      {Unit::DayOfYear, "day_of_year", "day", "day of the year (1 = January 1st)"},
      {Unit::Year, "yr", "yr", "years"},
      {Unit::PerSecond, "per_s", "1/s", "per second"},
      {Unit::PerYear, "per_yr", "1/yr", "per year"},
      {Unit::SecondPerMetre, "s_per_m", "s/m", "seconds per metre"},
      {Unit::MetrePerSecond, "m_per_s", "m/s", "metres per second"},
      {Unit::MetrePerSecondSquared, "m_per_s2", "m/s²", "metres per second squared"},
      {Unit::MetrePerYear, "m_per_yr", "m/yr", "metres per year"},
      {Unit::SquareMetrePerYear, "m2_per_yr", "m²/yr", "square metres per year"},
      {Unit::PerSquareMetre, "per_m2", "1/m²", "per square metre"},
      {Unit::PerSquareKilometre, "per_km2", "1/km²", "per square kilometre"},
      {Unit::CubicMetrePerSecond, "m3_per_s", "m³/s", "cubic metres per second"},
      {Unit::WattPerSquareMetre, "W_per_m2", "W/m²", "watts per square metre"},
      {Unit::Erodibility, "erodibility", "m^(1-2m)/yr", "stream-power erodibility (depends on the exponent m)"},
      {Unit::WidthCoefficient, "width_coefficient", "m/(m³/s)^b", "hydraulic-geometry width coefficient"},
  };
  return table;
}

const UnitInfo& unit_info(Unit unit) {
  for (const auto& u : all_units())
    if (u.unit == unit) return u;
  throw std::logic_error("unit without an entry in all_units()");
}

std::string_view unit_suffix(Unit unit) {
  switch (unit) {
    case Unit::None:
    case Unit::Unitless:
    case Unit::Count:
    case Unit::Id:
    case Unit::InputUnits:
      return "";
    default:
      return unit_symbol(unit);
  }
}

std::optional<Unit> unit_from_id(std::string_view id) {
  for (const auto& u : all_units())
    if (u.id == id) return u.unit;
  return std::nullopt;
}

}  // namespace orogen
