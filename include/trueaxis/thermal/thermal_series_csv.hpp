#pragma once
// Reader/writer of the thermal drift CSV format (docs/thermal-series.md).
//
// Columns are recognised by name, in any order:
//   time_s                  seconds, finite, strictly increasing (optional: without it rows are
//                           only ordered and time-based methods refuse the series); time_min and
//                           time_h are read as minutes and hours
//   position_mm             axis position the error was measured at (optional)
//   spindle_rpm             spindle speed, >= 0 (optional)
//   coolant                 off|flood|mist|air or 0..3 (optional)
//   t_<name>_c or <name>_C  a temperature in °C; empty or "nan" = not read
//   e_<name>_um or <name>_um an error channel in µm; empty or "nan" = not measured
//                           (none at all is allowed: a series to predict on; fitting refuses it)
// plus "# key: value" metadata lines before the header. Anything else is an
// InputError naming file, line and field. Missing values are kept as NaN
// here and handled by CleanSeries, never silently fitted.
//
// ThermalReadOptions maps the columns of files as users have them (an error column called
// "delta L", no header row, no time column) and states units. Without a stated unit the
// recording's units are checked against what a drift recording can be (core/plausibility.hpp
// SuspectTemperatureUnit, SuspectErrorUnit: refused, naming the column and the option that reads
// it; SuspectTimeUnit: a warning).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

enum class TemperatureUnit { kAuto, kCelsius, kFahrenheit, kKelvin };  // kAuto: °C, checked
enum class ErrorUnit { kAuto, kMicrometre, kMillimetre };                 // kAuto: µm, checked
bool ParseTemperatureUnit(const std::string& text, TemperatureUnit* out);  // C, F, K
bool ParseErrorUnit(const std::string& text, ErrorUnit* out);              // um (µm), mm
// Seconds per unit for s, min, h (nullopt otherwise).
std::optional<double> ParseTimeUnitS(const std::string& text);

struct ThermalReadOptions {
  TemperatureUnit temperature_unit = TemperatureUnit::kAuto;
  ErrorUnit error_unit = ErrorUnit::kAuto;
  // Columns read as error channels whatever their names (channel = the name with characters other
  // than letters, digits, '_' and '-' made '_'; "delta L" is channel delta_L).
  std::vector<std::string> error_columns;
  std::string time_column;  // the column read as time
  double time_unit_s = 0;   // seconds per unit of the time column; 0: from its name (_min, _h) or s
  double sample_interval_s = 0;  // > 0: a file without a time column sampled at this interval
  // The first row is data: columns are named col1..colN; those not named by time_column or
  // error_columns are temperatures in °C.
  bool no_header = false;
};

ThermalSeries ParseThermalSeriesCsv(std::string_view text, const std::string& source,
                                    const ThermalReadOptions& options = {}, std::vector<std::string>* warnings = nullptr);
ThermalSeries ReadThermalSeriesCsv(const std::string& path, const ThermalReadOptions& options = {},
                                   std::vector<std::string>* warnings = nullptr);
// A recording file as one or more experiments: a CSV file is one; an Excel workbook (.xlsx, read
// directly) gives one per worksheet that holds a recording, named "file.xlsx[Sheet]", with the
// spreadsheet's row numbers as line numbers. A sheet that is not a recording (notes, a chart's
// data) is skipped with a warning when another sheet is one; otherwise its error is thrown.
std::vector<ThermalSeries> ReadThermalSeriesFile(const std::string& path, std::vector<std::string>* warnings,
                                                 const ThermalReadOptions& options = {});
// Canonical form: time_s[,position_mm][,spindle_rpm][,coolant],t_<n>_c...,e_<n>_um...
// with shortest round-trip numbers; NaN written as an empty field.
std::string FormatThermalSeriesCsv(const ThermalSeries& series);
void WriteThermalSeriesCsv(const ThermalSeries& series, const std::string& path);

// fl_thermal.csv (../shared/data/fl_thermal/, CAIVIAC FL_THERMAL, MIT): columns
// time_s, spindle_rpm, ch1_um..ch5_um, t1_C..t16_C. Reads it with the generic
// reader and checks that exactly those columns are present, so a changed
// file is refused instead of half-imported.
ThermalSeries ImportFlThermalCsv(const std::string& path);

}  // namespace trueaxis::thermal
