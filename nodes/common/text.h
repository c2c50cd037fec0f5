#pragma once
// Small text helpers for the parsers of string parameters.
#include <string>
#include <string_view>

namespace orogen {

// The characters trim() removes: space, tab, carriage return, newline, form feed, vertical tab.
inline constexpr std::string_view kBlank = " \t\r\n\f\v";

// `s` without leading and trailing blanks (kBlank); empty if it holds nothing else.
inline std::string trim(std::string_view s) {
  const auto a = s.find_first_not_of(kBlank);
  if (a == std::string_view::npos) return {};
  return std::string(s.substr(a, s.find_last_not_of(kBlank) - a + 1));
}

}  // namespace orogen
