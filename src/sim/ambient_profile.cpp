#include "trueaxis/sim/ambient_profile.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::sim {

AmbientProfile::AmbientProfile(const AmbientDescription& d, std::uint64_t seed) : d_(d) {
  // Weather: four slow waves (2–9 days) with seeded phases, weighted so the
  // sum has the configured rms.
  std::mt19937_64 rng(seed ^ 0xA3B1E57ull);
  std::uniform_real_distribution<double> u(0, 1);
  double sum_sq = 0;
  for (int i = 0; i < 4; ++i) {
    weather_period_s_[i] = 86400.0 * (2.0 + 7.0 * u(rng));
    weather_phase_[i] = 2 * M_PI * u(rng);
    weather_weight_[i] = 0.5 + u(rng);
    sum_sq += weather_weight_[i] * weather_weight_[i] / 2;  // mean square of a sine
  }
  for (auto& w : weather_weight_) w *= d_.weather_amplitude_c / std::sqrt(sum_sq);
}

double AmbientProfile::TemperatureC(double unix_s) const {
  const double day = unix_s / 86400.0;
  const double day_of_year = std::fmod(day, 365.2425);  // close enough for a seasonal cosine
  const double hour = std::fmod(unix_s, 86400.0) / 3600.0;
  double t = d_.mean_c;
  t += d_.seasonal_amplitude_c * std::cos(2 * M_PI * (day_of_year - d_.seasonal_peak_day) / 365.2425);
  t += d_.daily_amplitude_c * std::cos(2 * M_PI * (hour - d_.daily_peak_hour) / 24.0);
  for (int i = 0; i < 4; ++i) t += weather_weight_[i] * std::sin(2 * M_PI * unix_s / weather_period_s_[i] + weather_phase_[i]);
  return t;
}

double ParseIsoTime(const std::string& iso) {
  int y, mo, d, h = 0, mi = 0, s = 0;
  char tail = 0;
  int n = std::sscanf(iso.c_str(), "%d-%d-%dT%d:%d:%d%c", &y, &mo, &d, &h, &mi, &s, &tail);
  if (n < 3 || n == 7 || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 || s < 0 || s > 60)
    throw std::invalid_argument("bad date-time '" + iso + "'");
  using namespace std::chrono;
  year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)}, day{static_cast<unsigned>(d)}};
  if (!ymd.ok()) throw std::invalid_argument("bad date '" + iso + "'");
  return static_cast<double>(sys_days{ymd}.time_since_epoch().count()) * 86400.0 + h * 3600.0 + mi * 60.0 + s;
}

std::string FormatIsoTime(double unix_s) {
  using namespace std::chrono;
  const auto secs = static_cast<long long>(std::floor(unix_s));
  const long long days = secs >= 0 ? secs / 86400 : (secs - 86399) / 86400;
  const long long rem = secs - days * 86400;
  year_month_day ymd{sys_days{std::chrono::days{days}}};
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                     static_cast<unsigned>(ymd.day()), rem / 3600, (rem / 60) % 60, rem % 60);
}

}  // namespace trueaxis::sim
