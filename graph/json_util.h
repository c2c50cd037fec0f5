#pragma once
// Small JSON helpers shared by the graph-file reader and writer: exact number text, strict parsing with
// positions and duplicate-key detection, and wording for diagnostics.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace orogen::json_util {

// The shortest decimal text that reads back as exactly `v` ("0.1", "800", "1e+300"; "-0.0" for minus zero).
// `v` must be finite.
std::string format_double(double v);
// The double of the shortest decimal text that reads back, through a double, as exactly `f`: writing this
// double with format_double gives "0.1" for 0.1f instead of "0.10000000149011612".
double float_as_short_double(float f);

// One problem found while parsing JSON text.
struct ParseProblem {
  std::string path;  // JSON pointer ("" for the document itself)
  std::string message;
};

// Parses strict JSON (no comments). Syntax errors give "malformed JSON at line L, column C: ..." and stop;
// a key repeated in one object is reported (with its path) but parsing goes on. Returns the document only
// when there was no syntax error.
std::optional<nlohmann::json> parse_strict(std::string_view text, std::vector<ParseProblem>& problems);

// Escapes one JSON-pointer reference token ("~" -> "~0", "/" -> "~1").
std::string pointer_token(std::string_view key);

// A short description of a JSON value for messages: the string "abc", the number 3.5, true, null,
// an array of 3 elements, an object.
std::string describe(const nlohmann::json& j);

// The candidate closest to `name` by case-insensitive edit distance, or "" if none is close enough to be a
// plausible typo.
std::string closest_name(std::string_view name, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or, when nothing is close, " (expected one of: a, b, c)"; "" when `candidates` is empty.
std::string suggestion(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace orogen::json_util
