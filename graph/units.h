#pragma once
// The units of parameters, ports and table columns: one closed list, each with its symbol and name, so a
// unit is never free text (docs/conventions.md, "Units"). Shown by the editor's inspector and `orogen nodes`;
// tests/test_registry_conventions.cpp refuses a numeric parameter without one.
#include <optional>
#include <string_view>
#include <vector>

namespace orogen {

enum class Unit {
  None,        // not declared: text, paths, enums, colors, booleans (refused on numbers by the registry test)
  Unitless,    // a pure number: a weight, share, exponent, coefficient or a 0..1 mask value
  Factor,      // x: a multiplier of another quantity
  Count,       // a number of things: octaves, iterations, samples, classes
  Id,          // an identifier: a class id, a biome id
  InputUnits,  // the units of the input field (metres after heights, degrees after Slope, 0..1 after a mask)
  Metre,
  SquareMetre,
  CubicMetre,
  PerMetre,
  MetrePerMetre,  // a gradient, rise over run
  Millimetre,
  MillimetrePerHour,
  Degree,
  DegreeCelsius,
  DegreeCelsiusPerKilometre,
  DegreeCelsiusPerHour,
  Millisecond,
  Second,
  Hour,
  DayOfYear,  // a date: day 1 (January 1st) .. 366
  Year,
  PerSecond,
  PerYear,
  SecondPerMetre,
  MetrePerSecond,
  MetrePerSecondSquared,
  MetrePerYear,
  SquareMetrePerYear,
  PerSquareMetre,
  PerSquareKilometre,
  CubicMetrePerSecond,
  WattPerSquareMetre,
  Erodibility,      // m^(1-2m)/yr: the stream-power law's K, whose dimension depends on the exponent m
  WidthCoefficient  // m/(m^3/s)^b: k of the hydraulic-geometry law w = k Q^b
};

struct UnitInfo {
  Unit unit;
  std::string_view id;      // stable, ASCII, as `orogen nodes --json` writes it: "m2", "degC", "mm_per_h"
  std::string_view symbol;  // as shown: "m²", "°C", "mm/h"; empty for None and Unitless
  std::string_view name;    // "square metres", "degrees Celsius"
};

const std::vector<UnitInfo>& all_units();
const UnitInfo& unit_info(Unit unit);
inline std::string_view unit_symbol(Unit unit) { return unit_info(unit).symbol; }
inline std::string_view unit_name(Unit unit) { return unit_info(unit).name; }
inline std::string_view unit_id(Unit unit) { return unit_info(unit).id; }
std::optional<Unit> unit_from_id(std::string_view id);
// What follows a number in a field or slider: the symbol of a physical unit or "x"; nothing for unitless
// numbers, counts, ids and the input's units.
std::string_view unit_suffix(Unit unit);

}  // namespace orogen
