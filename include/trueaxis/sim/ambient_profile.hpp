#pragma once
// AmbientProfile: the workshop air temperature as a pure function of absolute
// time: mean + seasonal cosine + daily cosine + a smooth multi-day random
// "weather" part whose phases come from the run seed.
#include <array>
#include <cstdint>

#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {

class AmbientProfile {
 public:
  AmbientProfile(const AmbientDescription& d, std::uint64_t seed);
  // unix_s: seconds since 1970-01-01T00:00:00 (UTC, simulated clock).
  double TemperatureC(double unix_s) const;

 private:
  AmbientDescription d_;
  std::array<double, 4> weather_period_s_{};
  std::array<double, 4> weather_phase_{};
  std::array<double, 4> weather_weight_{};
};

// "2026-03-02T07:00:00" ↔ unix seconds (UTC). Throws std::invalid_argument.
double ParseIsoTime(const std::string& iso);
std::string FormatIsoTime(double unix_s);

}  // namespace trueaxis::sim
