#pragma once
// Reads a measurement in whichever supported format it is in (docs/formats.md):
// the canonical CSV or the ecmc .dat. The format is decided by content first
// (a TGT_DATA[ / REF_DATA_ key or a TEST_DATA= first line means ecmc), then
// by extension (.dat), else CSV.
#include <string>
#include <string_view>

#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::measure {

enum class MeasurementFormat { kCanonicalCsv, kEcmcDat };

MeasurementFormat DetectMeasurementFormat(const std::string& path, std::string_view text);
const char* MeasurementFormatName(MeasurementFormat f);
Measurement ParseMeasurement(std::string_view text, const std::string& source, MeasurementFormat format);
// Reads, detects and parses; InputError on any problem.
Measurement ReadMeasurementFile(const std::string& path);

}  // namespace trueaxis::measure
