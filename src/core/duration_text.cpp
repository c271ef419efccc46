#include "trueaxis/core/duration_text.hpp"

#include <cmath>

#include <fmt/format.h>

namespace trueaxis {

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "—";
  if (seconds < 59.95) return fmt::format("{:.1f} s", seconds);
  const long long total_s = std::llround(seconds);
  if (total_s < 3600) return fmt::format("{} min {:02} s", total_s / 60, total_s % 60);
  const long long minutes = (total_s + 30) / 60;  // to the nearest minute from an hour up
  const long long days = minutes / 1440, hours = minutes / 60 % 24, mins = minutes % 60;
  if (days == 0) return fmt::format("{}:{:02} h", hours, mins);
  return fmt::format("{} d {:02}:{:02}", days, hours, mins);
}

}  // namespace trueaxis
