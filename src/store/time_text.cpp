#include "trueaxis/store/time_text.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>

#include <fmt/format.h>

#include "trueaxis/core/number_text.hpp"

namespace trueaxis::store {

std::string FormatUtc(double time_s) {
  if (!std::isfinite(time_s)) return "";
  double whole = std::floor(time_s);
  long long ms = std::llround((time_s - whole) * 1000.0);
  if (ms == 1000) {
    whole += 1;
    ms = 0;
  }
  const std::time_t t = static_cast<std::time_t>(whole);
  std::tm tm{};
  if (!gmtime_r(&t, &tm)) return "";
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
}

std::optional<double> ParseTimeText(std::string_view text) {
  text = Trim(text);
  if (text.empty()) return std::nullopt;
  if (auto v = ParseDouble(text); v && std::isfinite(*v)) return v;
  std::string s(text);
  double zone_offset_s = 0;  // "+08:00" means the clock time is 8 h ahead of UTC
  if (!s.empty() && (s.back() == 'Z' || s.back() == 'z')) {
    s.pop_back();
  } else if (s.size() > 16 && (s[s.size() - 6] == '+' || s[s.size() - 6] == '-') && s[s.size() - 3] == ':') {
    int zh = 0, zm = 0;
    if (std::sscanf(s.c_str() + s.size() - 5, "%2d:%2d", &zh, &zm) != 2 || zh > 14 || zm > 59) return std::nullopt;
    zone_offset_s = (s[s.size() - 6] == '+' ? 1 : -1) * (zh * 3600.0 + zm * 60.0);
    s.resize(s.size() - 6);
  }
  int year = 0, mon = 0, day = 0, hour = 0, min = 0;
  double sec = 0;
  int consumed = 0;
  const int fields = std::sscanf(s.c_str(), "%4d-%2d-%2d%n", &year, &mon, &day, &consumed);
  if (fields != 3) return std::nullopt;
  std::size_t pos = static_cast<std::size_t>(consumed);
  if (pos < s.size()) {
    if (s[pos] != 'T' && s[pos] != 't' && s[pos] != ' ') return std::nullopt;
    int c2 = 0;
    const std::string rest = s.substr(pos + 1);
    if (std::sscanf(rest.c_str(), "%2d:%2d%n", &hour, &min, &c2) != 2) return std::nullopt;
    std::string tail = rest.substr(static_cast<std::size_t>(c2));
    if (!tail.empty()) {
      if (tail[0] != ':') return std::nullopt;
      auto v = ParseDouble(tail.substr(1));
      if (!v || *v < 0 || *v >= 61) return std::nullopt;
      sec = *v;
    }
  }
  if (mon < 1 || mon > 12 || day < 1 || day > 31 || hour < 0 || hour > 23 || min < 0 || min > 59) return std::nullopt;
  std::tm tm{};
  tm.tm_year = year - 1900;
  tm.tm_mon = mon - 1;
  tm.tm_mday = day;
  tm.tm_hour = hour;
  tm.tm_min = min;
  tm.tm_sec = 0;
  const std::time_t t = timegm(&tm);
  // timegm normalises 2026-02-31 to March: refuse dates that do not exist.
  std::tm check{};
  gmtime_r(&t, &check);
  if (check.tm_mday != day || check.tm_mon != mon - 1) return std::nullopt;
  return static_cast<double>(t) + sec - zone_offset_s;
}

}  // namespace trueaxis::store
