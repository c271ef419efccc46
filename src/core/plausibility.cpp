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

std::optional<std::string> ImplausibleExpansionUmPerMmPerC(double v) {
  if (!std::isfinite(v)) return "not a finite expansion";
  if (std::abs(v) <= kMaxPlausibleExpansionUmPerMmPerC) return std::nullopt;
  return fmt::format("{} µm/mm/°C is beyond ±{} µm/mm/°C (steel is about 0.0115; wrong unit: µm/m/°C instead of "
                     "µm/mm/°C?)", v, kMaxPlausibleExpansionUmPerMmPerC);
}

std::optional<std::string> ImplausibleCteUmPerMC(double v) {
  if (!std::isfinite(v)) return "not a finite expansion coefficient";
  if (std::abs(v) <= kMaxPlausibleCteUmPerMC) return std::nullopt;
  return fmt::format("{} µm/m/°C is beyond ±{} µm/m/°C (steel is about 11.5; wrong unit: nm/m/°C?)", v,
                     kMaxPlausibleCteUmPerMC);
}

std::optional<std::string> UnusualCteUmPerMC(double v) {
  if (v >= 0 && v <= kMaxUsualCteUmPerMC) return std::nullopt;
  if (v < 0)
    return fmt::format("{} µm/m/°C is negative: the screw shrinks as it warms ({}steel is about +11.5): check the "
                       "sign", v, v >= kMinUsualCteUmPerMC ? "Invar or carbon fibre can; " : "");
  return fmt::format("{} µm/m/°C is unusual for a screw (above {} µm/m/°C; steel is about 11.5)", v, kMaxUsualCteUmPerMC);
}

}  // namespace trueaxis
