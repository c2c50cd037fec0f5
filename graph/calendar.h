#pragma once
// Days and months of a common (non-leap) year: the one calendar behind SunIllumination's monthly declination
// and the graph-format migration of its former `month` parameter to `day_of_year` (version 6).
#include <algorithm>
#include <array>
#include <cstddef>

namespace orogen::calendar {

// Day of the year (1 = January 1st) on which each month starts.
inline constexpr std::array<int, 12> kMonthStart = {1, 32, 60, 91, 121, 152, 182, 213, 244, 274, 305, 335};

// The month 1..12 that holds `day_of_year` (1..365; 366 and later count as December, 0 and less as January).
constexpr int month_of_day(int day_of_year) {
  int month = 1;
  while (month < 12 && day_of_year >= kMonthStart[static_cast<std::size_t>(month)]) ++month;
  return month;
}

// The 15th of `month` (clamped to 1..12): month_of_day(mid_month_day(m)) == m.
constexpr int mid_month_day(int month) {
  return kMonthStart[static_cast<std::size_t>(std::clamp(month, 1, 12) - 1)] + 14;
}

}  // namespace orogen::calendar
