#pragma once
// Reader and writer of the canonical measurement file (docs/formats.md):
//
//   # axis: X
//   # machine: VMC-850
//   run,direction,target_mm,deviation_um,time_s,t_nut_c,t_air_c
//   1,+,0,0.8,12.5,20.41,20.02
//
// Lines starting with '#' carry "key: value" metadata; the header names the
// columns; run, direction, target_mm and deviation_um are required, time_s and
// t_<sensor>_c columns optional, in any order. Unknown columns are an error
// (a typo in a sensor column must not be silently dropped).
//
// ReadMeasurementCsv throws InputError(file, line, field, why) on bad input.
// WriteMeasurementCsv writes shortest round-trip numbers, so
// Parse(Write(m)) == m exactly.
#include <string>
#include <string_view>

#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::measure {

Measurement ParseMeasurementCsv(std::string_view text, const std::string& source);
Measurement ReadMeasurementCsv(const std::string& path);

std::string FormatMeasurementCsv(const Measurement& m);
void WriteMeasurementCsv(const Measurement& m, const std::string& path);

}  // namespace trueaxis::measure
