#pragma once
// The one way a measurement is read, by every command (docs/formats.md): whichever supported
// format the file is in — the canonical CSV, the ecmc .dat, or a laser software's CSV export read
// through a column mapping (column_map.hpp) — with the same InputError(file, line, field) for bad
// input.
//
// The format is decided by content first (a TGT_DATA[ / REF_DATA_ key or a TEST_DATA= first line
// means ecmc), then by extension (.dat), else CSV. A CSV is read through the mapping when one is
// given and its header is not the canonical one (run, direction, target_mm, deviation_um), else as
// the canonical CSV — so canonical files and mapped exports can be given together.
#include <optional>
#include <string>
#include <string_view>

#include "trueaxis/measure/column_map.hpp"
#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::measure {

enum class MeasurementFormat { kCanonicalCsv, kEcmcDat, kMappedCsv };

struct MeasurementReadOptions {
  std::optional<ColumnMap> columns;  // a laser software's columns (--columns / --column-map)
};

MeasurementFormat DetectMeasurementFormat(const std::string& path, std::string_view text,
                                          const MeasurementReadOptions& options = {});
const char* MeasurementFormatName(MeasurementFormat f);
// Detects and parses `text` (the file's content; `source` names it in errors).
Measurement ParseMeasurement(std::string_view text, const std::string& source, const MeasurementReadOptions& options = {});
// Reads, detects and parses; InputError on any problem.
Measurement ReadMeasurementFile(const std::string& path, const MeasurementReadOptions& options = {});

}  // namespace trueaxis::measure
