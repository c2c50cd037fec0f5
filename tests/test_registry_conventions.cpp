// The glossary and the units of docs/conventions.md, checked on every registered node type, so a new node that
// breaks them fails here: every number has a unit from the closed list (graph/units.h), no angle is in
// radians, one name per quantity, American spelling in names and descriptions, and display labels that are
// not empty.
#include <algorithm>
#include <cctype>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/units.h"
#include "support/registered_types.h"

namespace orogen {
namespace {

class RegistryConventions : public testing::TestWithParam<std::string> {
 protected:
  const NodeType& type() const { return *NodeRegistry::instance().find(GetParam()); }
};

bool is_number(ParamType t) {
  return t == orogen::ParamType::Float || t == orogen::ParamType::Int || t == orogen::ParamType::Vec2 ||
         t == orogen::ParamType::Vec3;
}

bool is_number_column(ColumnType t) {
  return t == ColumnType::Number || t == ColumnType::Integer || t == ColumnType::Range;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// British spellings a user would read; metre is the SI name of the unit and stays.
const char* const kBritish[] = {"centre",    "centred", "normalis", "colour",    "neighbour", "labelled",
                                "initialis", "analyse", "grey",     "behaviour", "organise",  "optimis",
                                "favour",    "minimis", "maximis",  "modell",    "travelled", "parametris"};

void expect_american(const std::string& where, const std::string& text) {
  const std::string l = lower(text);
  for (const char* word : kBritish)
    EXPECT_EQ(l.find(word), std::string::npos) << where << ": '" << word << "' in: " << text;
}

// Whether a parameter or column name names an angle: one of its '_'-separated words is an angle's name
// (talus_angle, sun_azimuth, latitude). `elevation` alone is a height in metres; the sun's is an angle.
bool name_is_angle(const std::string& name) {
  static const std::set<std::string> words = {"angle", "azimuth", "tilt", "dip",  "rotation", "heading",  "bearing",
                                              "yaw",   "pitch",   "roll", "turn", "latitude", "longitude"};
  if (name == "sun_elevation") return true;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('_', start), name.size());
    if (words.count(name.substr(start, end - start))) return true;
    start = end + 1;
  }
  return false;
}

// Whether a description speaks of an angle (degrees Celsius are a temperature).
bool description_mentions_angle(const std::string& description) {
  static const std::regex angle(
      R"(\b(angles?|azimuth|tilt|dip|rotations?|heading|bearing|yaw|pitch|roll|latitude|longitude|degrees?)\b)",
      std::regex::icase);
  static const std::regex celsius(R"(\bdegrees? celsius\b)", std::regex::icase);
  return std::regex_search(std::regex_replace(description, celsius, ""), angle);
}

// Numbers whose description speaks of an angle without being one, each with the reason.
const std::set<std::string> kMentionsAngleButIsNot = {
    "ProjectToTerrain.align",  // a blend factor 0..1 between keeping the rotation and following the normal
    "PipeErosion.capacity",    // a coefficient per sin(tilt) x speed x depth: the angle enters through its sine
};

// A number that names or describes an angle is in degrees: a radian angle declared Unitless (or Factor, or
// Count) fails here even when its description never says "radians". Returns the problem, empty if none.
std::string angle_unit_problem(const std::string& where, const std::string& name, const std::string& description,
                               Unit unit) {
  if (unit == Unit::Degree) return {};
  if (name_is_angle(name)) return where + ": its name is an angle's; angles are degrees";
  if (description_mentions_angle(description) && !kMentionsAngleButIsNot.count(where))
    return where + ": its description speaks of an angle (\"" + description +
           "\"); angles are degrees (or list it in kMentionsAngleButIsNot with the reason)";
  return {};
}

TEST_P(RegistryConventions, EveryNumberHasAUnitAndNoAngleIsInRadians) {
  for (const auto& p : type().params) {
    const std::string where = type().name + "." + p.name;
    if (is_number(p.type)) EXPECT_NE(p.unit, Unit::None) << where << " is a number without a unit";
    if (p.type == orogen::ParamType::Table)
      for (const auto& c : p.table.columns)
        if (is_number_column(c.type)) {
          EXPECT_NE(c.unit, Unit::None) << where << "." << c.name << " is a number column without a unit";
          EXPECT_EQ(angle_unit_problem(where + "." + c.name, c.name, c.description, c.unit), "");
        }
    // Angles are degrees: a description that speaks of radians marks a radian angle.
    static const std::regex radians(R"(\bradians?\b)", std::regex::icase);
    EXPECT_FALSE(std::regex_search(p.description, radians)) << where << ": " << p.description;
    if (is_number(p.type)) EXPECT_EQ(angle_unit_problem(where, p.name, p.description, p.unit), "");
    if (p.unit == Unit::Degree && p.min && p.max) {
      EXPECT_GE(*p.max - *p.min, 6.3) << where << ": a range this narrow reads like radians";
    }
  }
}

// The angle rule itself: it must catch a radian angle declared Unitless, by name or by description, and leave
// alone heights called elevation, temperatures in degrees Celsius and words that merely contain an angle's.
TEST(RegistryConventionsRule, AnglesAreRecognizedByNameAndDescription) {
  EXPECT_TRUE(name_is_angle("angle"));
  EXPECT_TRUE(name_is_angle("talus_angle"));
  EXPECT_TRUE(name_is_angle("sun_azimuth"));
  EXPECT_TRUE(name_is_angle("sun_elevation"));
  EXPECT_TRUE(name_is_angle("rotation_jitter"));
  EXPECT_TRUE(name_is_angle("max_tilt"));
  EXPECT_FALSE(name_is_angle("elevation"));
  EXPECT_FALSE(name_is_angle("rolling"));
  EXPECT_FALSE(name_is_angle("dipole"));
  EXPECT_FALSE(name_is_angle("anglers"));
  EXPECT_TRUE(description_mentions_angle("Rotation about z of each instance"));
  EXPECT_TRUE(description_mentions_angle("Branch angle"));
  EXPECT_TRUE(description_mentions_angle("Tilt of the layer"));
  EXPECT_TRUE(description_mentions_angle("Latitude, north positive"));
  EXPECT_FALSE(description_mentions_angle("Air temperature at sea level, degrees Celsius"));
  EXPECT_FALSE(description_mentions_angle("Preferred elevation [min, max] in metres"));
  EXPECT_FALSE(description_mentions_angle("Rolling hills of the base terrain"));
  // What the registry test then asks: such a number declared Unitless fails, in degrees it passes, and the
  // listed exceptions pass whatever their unit.
  EXPECT_NE(angle_unit_problem("X.rotation", "rotation", "Rotation about z", Unit::Unitless), "");
  EXPECT_NE(angle_unit_problem("X.spin", "spin", "Turn about the axis, in rotations", Unit::Factor), "");
  EXPECT_NE(angle_unit_problem("X.bend", "bend", "Branch angle from the parent", Unit::Count), "");
  EXPECT_EQ(angle_unit_problem("X.rotation", "rotation", "Rotation about z", Unit::Degree), "");
  EXPECT_EQ(angle_unit_problem("X.height", "elevation", "Preferred elevation in metres", Unit::Metre), "");
  EXPECT_EQ(angle_unit_problem("ProjectToTerrain.align", "align", "keep the rotation", Unit::Unitless), "");
}

TEST_P(RegistryConventions, GlossaryNames) {
  const NodeType& t = type();
  for (const auto& p : t.params) {
    const std::string where = t.name + "." + p.name;
    expect_american(where, p.name + " " + p.description);
    for (const auto& c : p.table.columns) expect_american(where + "." + c.name, c.name + " " + c.description);
    EXPECT_FALSE(p.display_label().empty()) << where;
    // `seed` is a random seed and nothing else; a seed is never called anything but `seed` or `*_seed`.
    if (p.name == "seed" || p.name.ends_with("_seed")) EXPECT_EQ(p.type, orogen::ParamType::Seed) << where;
    if (p.type == orogen::ParamType::Seed) EXPECT_TRUE(p.name == "seed" || p.name.ends_with("_seed")) << where;
    EXPECT_FALSE(p.name.starts_with("seed_")) << where << ": `seed` is only a random seed";
    // Temperatures in degrees Celsius.
    // A weight of a channel named after a quantity (KMeansClusters' weight_slope) is not that quantity.
    if (p.name.starts_with("weight_")) continue;
    const bool temperature_name = p.name.ends_with("temperature") || p.name.starts_with("t_");
    EXPECT_EQ(temperature_name, p.unit == Unit::DegreeCelsius) << where << ": temperatures are in °C";
    // One name for the sun, the date and vertical exaggeration.
    for (const char* banned : {"azimuth", "altitude", "month", "height_scale", "rain_rate", "water"})
      EXPECT_NE(p.name, banned) << where << ": see the glossary";
    if (p.name == "sun_azimuth" || p.name == "sun_elevation") EXPECT_EQ(p.unit, Unit::Degree) << where;
    if (p.name == "day_of_year") EXPECT_EQ(p.unit, Unit::DayOfYear) << where;
    if (p.name == "z_factor") EXPECT_EQ(p.unit, Unit::Factor) << where;
    // Slope is an angle in degrees; rise over run is a gradient.
    if (p.name == "slope" || p.name.ends_with("_slope")) EXPECT_EQ(p.unit, Unit::Degree) << where;
    if (p.unit == Unit::MetrePerMetre) EXPECT_NE(p.name.find("gradient"), std::string::npos) << where;
    // Rainfall: a depth in mm, a rate in mm/h.
    if (p.name == "rainfall") EXPECT_EQ(p.unit, Unit::Millimetre) << where;
    if (p.name == "rainfall_rate") EXPECT_EQ(p.unit, Unit::MillimetrePerHour) << where;
  }
  auto check_port = [&](const PortDecl& p, bool output) {
    const std::string where = t.name + "." + p.name;
    EXPECT_NE(p.name, "water") << where << ": water_depth (m) or water_mask (0..1)";
    EXPECT_NE(p.name, "depth") << where << ": water_depth";
    EXPECT_NE(p.name, "temperature_factor") << where;
    // A color image is `color`, never `image` (writers read any image on `in`).
    if (output) EXPECT_NE(p.name, "image") << where << ": a color output is `color`";
    if (p.name.ends_with("temperature")) EXPECT_EQ(p.unit, Unit::DegreeCelsius) << where;
    if (p.name == "rainfall") EXPECT_EQ(p.unit, Unit::Millimetre) << where;
    if (p.name == "rainfall_rate") EXPECT_EQ(p.unit, Unit::MillimetrePerHour) << where;
    if (p.name == "rainfall_weight") EXPECT_EQ(p.unit, Unit::Unitless) << where;
    if (p.name == "water_depth") EXPECT_EQ(p.unit, Unit::Metre) << where;
    if (p.name == "slope") EXPECT_EQ(p.unit, Unit::Degree) << where;
    if (p.name == "gradient") EXPECT_EQ(p.unit, Unit::MetrePerMetre) << where;
    if (p.name.ends_with("_mask")) {
      EXPECT_EQ(p.unit, Unit::Unitless) << where;
      if (output) EXPECT_EQ(p.kind, OutputKind::Mask) << where;
    }
    expect_american(where, p.name + " " + p.description);
    EXPECT_FALSE(p.display_label().empty()) << where;
  };
  for (const auto& p : t.inputs) check_port(p, false);
  for (const auto& p : t.outputs) check_port(p, true);
  expect_american(t.name, t.name + " " + t.description);
}

INSTANTIATE_TEST_SUITE_P(AllTypes, RegistryConventions, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

TEST(Units, EveryUnitHasAnIdANameAndOneEntry) {
  std::set<std::string_view> ids;
  std::set<Unit> units;
  for (const auto& u : all_units()) {
    EXPECT_FALSE(u.id.empty());
    EXPECT_FALSE(u.name.empty());
    EXPECT_TRUE(ids.insert(u.id).second) << u.id;
    EXPECT_TRUE(units.insert(u.unit).second) << u.id;
    EXPECT_EQ(unit_from_id(u.id), u.unit) << u.id;
    EXPECT_EQ(unit_info(u.unit).id, u.id);
    for (const char c : u.id) EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c)) || c == '_') << u.id;
  }
  EXPECT_FALSE(unit_from_id("metres"));
  EXPECT_EQ(unit_symbol(Unit::DegreeCelsius), "°C");
  EXPECT_EQ(unit_suffix(Unit::Count), "");
  EXPECT_EQ(unit_suffix(Unit::SquareMetre), "m²");
}

TEST(Labels, DefaultToThePrettifiedIdentifier) {
  EXPECT_EQ(prettify_identifier("sun_azimuth"), "Sun azimuth");
  EXPECT_EQ(prettify_identifier("in"), "In");
  EXPECT_EQ(prettify_identifier("z_factor"), "Z factor");
  EXPECT_EQ(prettify_identifier(""), "");
  PortDecl port;
  port.name = "water_depth";
  EXPECT_EQ(port.display_label(), "Water depth");
  port.label = "Standing water";
  EXPECT_EQ(port.display_label(), "Standing water");
}

}  // namespace
}  // namespace orogen
