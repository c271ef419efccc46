#include "trueaxis/campaign/campaign_clock.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include <fmt/format.h>

namespace trueaxis::campaign {

std::optional<double> ParseCampaignDate(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  const std::string s(text);
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, consumed = 0;
  char sep = 0;
  if (std::sscanf(s.c_str(), "%4d-%2d-%2d%c%2d:%2d%n", &y, &mo, &d, &sep, &h, &mi, &consumed) != 6) return std::nullopt;
  if (sep != 'T' && sep != ' ') return std::nullopt;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59) return std::nullopt;
  std::size_t i = static_cast<std::size_t>(consumed);
  double sec = 0;
  if (i < s.size() && s[i] == ':') {
    std::size_t j = i + 1;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
    if (j == i + 1) return std::nullopt;
    try {
      sec = std::stod(s.substr(i + 1, j - i - 1));
    } catch (...) {
      return std::nullopt;
    }
    if (!(sec >= 0 && sec < 61)) return std::nullopt;
    i = j;
  }
  std::tm tm{};
  tm.tm_year = y - 1900;
  tm.tm_mon = mo - 1;
  tm.tm_mday = d;
  tm.tm_hour = h;
  tm.tm_min = mi;
  tm.tm_sec = 0;
  const std::string zone = s.substr(i);
  double base = 0;
  if (zone.empty()) {
    tm.tm_isdst = -1;
    const std::time_t t = std::mktime(&tm);
    if (t == static_cast<std::time_t>(-1)) return std::nullopt;
    base = static_cast<double>(t);
  } else {
    const std::time_t t = timegm(&tm);
    base = static_cast<double>(t);
    if (zone == "Z" || zone == "z") {
      // UTC
    } else {
      int oh = 0, om = 0;
      char sign = 0;
      if (std::sscanf(zone.c_str(), "%c%2d:%2d", &sign, &oh, &om) != 3 || (sign != '+' && sign != '-') || zone.size() != 6)
        return std::nullopt;
      base -= (sign == '+' ? 1 : -1) * (oh * 3600.0 + om * 60.0);
    }
  }
  return base + sec;
}

std::string FormatCampaignDate(double unix_s, int decimals) {
  const double whole = std::floor(unix_s);
  const std::time_t t = static_cast<std::time_t>(whole);
  std::tm tm{};
  localtime_r(&t, &tm);
  std::string out = fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                                tm.tm_hour, tm.tm_min, tm.tm_sec);
  if (decimals > 0) {
    const double scale = std::pow(10.0, decimals);
    const long frac = std::min(static_cast<long>(std::floor((unix_s - whole) * scale)), static_cast<long>(scale) - 1);
    out += fmt::format(".{:0{}}", frac, decimals);
  }
  return out;
}

double WallClockNowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace trueaxis::campaign
