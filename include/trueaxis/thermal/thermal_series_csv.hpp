#pragma once
// Reader/writer of the thermal drift CSV format (docs/thermal-series.md).
//
// Columns are recognised by name, in any order:
//   time_s                  seconds, finite, strictly increasing (optional: without it rows are
//                           only ordered and time-based methods refuse the series)
//   position_mm             axis position the error was measured at (optional)
//   spindle_rpm             spindle speed, >= 0 (optional)
//   coolant                 off|flood|mist|air or 0..3 (optional)
//   t_<name>_c or <name>_C  a temperature in °C; empty or "nan" = not read
//   e_<name>_um or <name>_um an error channel in µm; empty or "nan" = not measured
//                           (none at all is allowed: a series to predict on; fitting refuses it)
// plus "# key: value" metadata lines before the header. Anything else is an
// InputError naming file, line and field. Missing values are kept as NaN
// here and handled by CleanSeries, never silently fitted.
#include <string>
#include <string_view>
#include <vector>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

ThermalSeries ParseThermalSeriesCsv(std::string_view text, const std::string& source);
ThermalSeries ReadThermalSeriesCsv(const std::string& path);
// A recording file as one or more experiments: a CSV file is one; an Excel workbook (.xlsx, read
// directly) gives one per worksheet that holds a recording, named "file.xlsx[Sheet]", with the
// spreadsheet's row numbers as line numbers. A sheet that is not a recording (notes, a chart's
// data) is skipped with a warning when another sheet is one; otherwise its error is thrown.
std::vector<ThermalSeries> ReadThermalSeriesFile(const std::string& path, std::vector<std::string>* warnings);
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
