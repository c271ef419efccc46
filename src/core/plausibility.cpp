#include "trueaxis/core/plausibility.hpp"

#include <cmath>

#include <fmt/format.h>

namespace trueaxis {

std::optional<std::string> ImplausibleTemperatureC(double v) {
  if (!std::isfinite(v)) return "not a finite temperature";
  if (v >= kMinPlausibleTemperatureC && v <= kMaxPlausibleTemperatureC) return std::nullopt;
  if (v >= 223 && v <= 423)
    return fmt::format("{} °C is not plausible on a machine tool; it looks like kelvin ({:.2f} °C); give °C",
                       v, v - 273.15);
  if (v >= 1000 && v <= 10000)
    return fmt::format("{} °C is not plausible on a machine tool; a missing decimal point or a unit "
                       "of 0.01 °C or 0.1 °C? give °C", v);
  return fmt::format("{} °C is outside the plausible {} … {} °C", v, kMinPlausibleTemperatureC,
                     kMaxPlausibleTemperatureC);
}

std::optional<std::string> ImplausiblePositionMm(double v) {
  if (!std::isfinite(v)) return "not a finite position";
  if (std::abs(v) <= kMaxPlausiblePositionMm) return std::nullopt;
  return fmt::format("{} mm is beyond ±{} mm (wrong unit: µm or nm instead of mm?)", v, kMaxPlausiblePositionMm);
}

std::optional<std::string> ImplausibleDeviationUm(double v) {
  if (!std::isfinite(v)) return "not a finite deviation";
  if (std::abs(v) <= kMaxPlausibleDeviationUm) return std::nullopt;
  return fmt::format("{} µm is beyond ±{} µm for a positioning deviation (wrong unit: nm instead of µm?)", v,
                     kMaxPlausibleDeviationUm);
}

std::optional<std::string> ImplausibleTimeS(double v) {
  if (!std::isfinite(v)) return "not a finite time";
  if (std::abs(v) <= kMaxPlausibleTimeS) return std::nullopt;
  return fmt::format("{} s is beyond ±{:g} s", v, kMaxPlausibleTimeS);
}

std::optional<std::string> ImplausibleFeedMmPerMin(double v) {
  if (!std::isfinite(v)) return "not a finite feed";
  if (v <= 0) return fmt::format("{} mm/min: a feed must be positive", v);
  if (v <= kMaxPlausibleFeedMmPerMin) return std::nullopt;
  return fmt::format("{} mm/min is beyond {:g} mm/min (wrong unit: µm/min instead of mm/min?)", v,
                     kMaxPlausibleFeedMmPerMin);
}

}  // namespace trueaxis
