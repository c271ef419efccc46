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

UnitSuspicion SuspectTemperatureUnit(double coolest_median_c) {
  if (!std::isfinite(coolest_median_c) || coolest_median_c <= kMaxPlausibleCoolestSensorC) return {};
  // Beyond both (and beyond a machine in °F): no unit makes it plausible; ImplausibleTemperatureC says so.
  if (coolest_median_c > kMaxPlausibleTemperatureC && coolest_median_c < kMinKelvinLikeTemperature) return {};
  if (coolest_median_c > kMaxKelvinLikeTemperature) return {};
  if (coolest_median_c >= kMinKelvinLikeTemperature)
    return {SuspectedUnit::kKelvin,
            fmt::format("even the coolest sensor reads {:g} (median): that is {:.1f} °C if it is kelvin", coolest_median_c,
                        coolest_median_c - 273.15)};
  return {SuspectedUnit::kFahrenheit,
          fmt::format("even the coolest sensor reads {:g} (median), hotter than a machine tool's shop ({} °C at most); "
                      "that is {:.1f} °C if it is °F", coolest_median_c, kMaxPlausibleCoolestSensorC,
                      (coolest_median_c - 32) * 5 / 9)};
}

UnitSuspicion SuspectErrorUnit(double max_abs_um, double rms_um) {
  if (!(max_abs_um > 0) || max_abs_um >= kMaxMillimetreLikeErrorAbs || rms_um >= kMaxMillimetreLikeErrorRms) return {};
  return {SuspectedUnit::kMillimetre,
          fmt::format("every value lies within ±{:g} with an RMS of {:.3g}: a thermal drift of less than {:g} µm is "
                      "below what is worth compensating, but {:.0f} µm if the values are mm", kMaxMillimetreLikeErrorAbs,
                      rms_um, kMaxMillimetreLikeErrorAbs, 1000 * max_abs_um)};
}

UnitSuspicion SuspectTimeUnit(double largest_range_c, double duration_s) {
  if (!(duration_s > 0) || !std::isfinite(largest_range_c)) return {};
  const double rate_c_per_h = largest_range_c / duration_s * 3600;
  if (rate_c_per_h <= kMaxPlausibleRecordingRateCPerH) return {};
  return {SuspectedUnit::kMinutes,
          fmt::format("a sensor changes by {:.3g} °C within the {:g} s recorded ({:.0f} °C/h), faster than machine "
                      "structures warm (at most {:g} °C/h); {:.0f} °C/h if the time is in minutes", largest_range_c,
                      duration_s, rate_c_per_h, kMaxPlausibleRecordingRateCPerH, rate_c_per_h / 60)};
}

}  // namespace trueaxis
