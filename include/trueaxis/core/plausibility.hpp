#pragma once
// Plausibility limits of the physical quantities trueaxis reads, so that a
// value a machine tool cannot have is refused with the file, line and field
// instead of flowing on (a 1e308 deviation made A = inf; kelvin temperatures
// passed a −100…500 °C check and made a −19 mm correction). Each check returns
// nothing when the value is plausible, else the reason, for an InputError.
//
// The limits are wide on purpose — they catch wrong units and garbage, not
// bad machines:
//   temperature   −50 … 150 °C        (a value in 223 … 423 is named as likely kelvin)
//   position      |x| ≤ 100 000 mm    (100 m: longer than any machine axis)
//   deviation     |e| ≤ 10 000 µm     (10 mm: no laser run of a working axis is that far off)
//   time          |t| ≤ 1e10 s        (since the start of a test or a campaign)
//   feed          0 < f ≤ 1e6 mm/min  (16.7 m/s: above any machine's rapid; slow feeds are
//                                      legitimate — bound the work they cause instead)
//   expansion     |ρ|, |k| ≤ 1 µm/mm/°C (1000 µm/m/°C: ~90× steel; a thermal gain or ρ of a model)
//   screw CTE     |cte| ≤ 1000 µm/m/°C  (refused beyond; outside −5 … 50, e.g. negative, only unusual)
#include <optional>
#include <string>

namespace trueaxis {

inline constexpr double kMinPlausibleTemperatureC = -50;
inline constexpr double kMaxPlausibleTemperatureC = 150;
inline constexpr double kMaxPlausiblePositionMm = 100000;
inline constexpr double kMaxPlausibleDeviationUm = 10000;
inline constexpr double kMaxPlausibleTimeS = 1e10;
inline constexpr double kMaxPlausibleFeedMmPerMin = 1e6;
inline constexpr double kMaxPlausibleExpansionUmPerMmPerC = 1;
inline constexpr double kMaxPlausibleCteUmPerMC = 1000;
inline constexpr double kMinUsualCteUmPerMC = -5;  // Invar, carbon fibre: near 0 or slightly negative
inline constexpr double kMaxUsualCteUmPerMC = 50;

std::optional<std::string> ImplausibleTemperatureC(double value_c);
std::optional<std::string> ImplausiblePositionMm(double value_mm);
std::optional<std::string> ImplausibleDeviationUm(double value_um);
std::optional<std::string> ImplausibleTimeS(double value_s);
std::optional<std::string> ImplausibleFeedMmPerMin(double value_mm_per_min);
// A thermal expansion per mm of lever and °C (the model's ρ and key gains k).
std::optional<std::string> ImplausibleExpansionUmPerMmPerC(double value);
// A screw's coefficient of thermal expansion: refused when not finite or beyond ±1000 µm/m/°C.
std::optional<std::string> ImplausibleCteUmPerMC(double value);
// A plausible CTE no common screw has (negative, or above 50 µm/m/°C): the text of a warning
// (−5 … 0: Invar, carbon fibre; below: a sign error more likely).
std::optional<std::string> UnusualCteUmPerMC(double value);

// Units of a whole recording (a thermal drift recording: temperatures in °C, errors in µm, time in
// s), judged from its columns together, which say more than one value can. Each returns nothing
// when the recording reads as labelled, else the reason and the unit it more likely is in:
//  - temperatures: a machine tool's coolest sensor (ambient, bed, column) sits near room
//    temperature, so a recording whose coolest sensor has a median above 45 °C reads like °F (a
//    15 … 30 °C shop is 59 … 86 °F; spindle and motor sensors may well be hotter, hence the
//    coolest) up to 150, and one in 223 … 423 like kelvin (others fit no unit: refused per value);
//  - an error channel: a thermal drift worth compensating moves by micrometres, so a channel whose
//    values all lie within ±0.2 with an RMS below 0.05 (not all zero) reads like mm (0.2 mm is
//    200 µm);
//  - time: machine structures warm by a few °C/h (a spindle warm-up 5 … 20 °C/h); a sensor whose
//    range over the whole recording comes faster than 60 °C/h reads like time in minutes.
inline constexpr double kMaxPlausibleCoolestSensorC = 45;
inline constexpr double kMinKelvinLikeTemperature = 223;
inline constexpr double kMaxKelvinLikeTemperature = 423;
inline constexpr double kMaxMillimetreLikeErrorAbs = 0.2;
inline constexpr double kMaxMillimetreLikeErrorRms = 0.05;
inline constexpr double kMaxPlausibleRecordingRateCPerH = 60;

enum class SuspectedUnit { kNone, kFahrenheit, kKelvin, kMillimetre, kMinutes };
struct UnitSuspicion {
  SuspectedUnit unit = SuspectedUnit::kNone;
  std::string why;  // empty when unit is kNone
  explicit operator bool() const { return unit != SuspectedUnit::kNone; }
};
UnitSuspicion SuspectTemperatureUnit(double coolest_median_c);
UnitSuspicion SuspectErrorUnit(double max_abs_um, double rms_um);
UnitSuspicion SuspectTimeUnit(double largest_range_c, double duration_s);

}  // namespace trueaxis
