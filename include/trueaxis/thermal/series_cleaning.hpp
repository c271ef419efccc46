#pragma once
// What happens to imperfect recordings before a model sees them
// (docs/thermal-series.md "Bad input"). The rules, in order:
//  1. Time: a step longer than max_time_step_factor x the median step is a
//     gap in the recording: InputError naming the line (a trend-based model
//     would see a jump), unless allow_time_gaps.
//  2. A temperature channel whose missing (NaN) readings cannot be filled —
//     all missing, missing at the start or the end (the sensor came up late
//     or died half way), or an interior run longer than
//     max_interpolated_gap_samples — is dropped with a warning
//     (drop_bad_temperature_channels) or refused with InputError.
//  3. A temperature channel whose standard deviation is below
//     min_temperature_std_c is constant: it carries no information and
//     breaks standardisation, so it is dropped with a warning — unless every
//     channel is constant (a table taken at one temperature, seed 003's Z
//     axis at 27.6 °C): then they are kept, with a warning.
//  4. Interior runs of at most max_interpolated_gap_samples missing values
//     (temperatures and errors) are filled by linear interpolation in time
//     and counted in the report, with a warning per column (how many, from
//     which line).
//  5. An error channel with a gap that rule 4 cannot fill is refused with
//     InputError (the target of a fit is never invented); a constant error
//     channel only gets a warning.
//  6. No temperature channel left: InputError.
#include <string>
#include <vector>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

struct SeriesCleaningOptions {
  int max_interpolated_gap_samples = 4;
  double min_temperature_std_c = 1e-3;
  bool drop_bad_temperature_channels = true;
  double max_time_step_factor = 10.0;
  bool allow_time_gaps = false;
  // false: error channels are left as they are (prediction needs only
  // temperatures; rules 4-5 do not apply to errors).
  bool check_error_channels = true;

  bool IsValid(std::string* why) const;
};

struct SeriesCleaningReport {
  std::vector<std::string> warnings;
  std::vector<std::string> dropped_temperatures;
  int interpolated_values = 0;

  std::string BriefReport() const;
};

ThermalSeries CleanSeries(const ThermalSeries& series, const SeriesCleaningOptions& options,
                          SeriesCleaningReport* report);

}  // namespace trueaxis::thermal
