#pragma once
// Reader of a laser software's own CSV export through a column mapping (column_map.hpp,
// docs/formats.md "Mapped CSV"): the header is the first line holding every mapped column
// (lines before it, e.g. the software's preamble, are skipped; '# key: value' lines are metadata),
// columns not mapped are ignored, rows whose mapped fields are all empty are skipped.
//
// Refused with InputError(file, line, field) — field being the column as the file names it:
// a mapped column missing from the header (or named twice in it); a column whose name states a
// unit other than its key's ("Error [mm]" mapped as deviation_um: map deviation_mm to convert); a
// row with another field count than the header; a value that is not a number, a run number or a
// direction word (MappedDirection); values outside the plausibility limits after conversion.
// A mapping that cannot make a positioning test (no target; neither run + direction + deviation
// nor one deviation column per run and direction; both layouts at once) is refused naming the
// mapping's source and the missing key.
#include <string>
#include <string_view>

#include "trueaxis/measure/column_map.hpp"
#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::measure {

Measurement ParseMappedCsv(std::string_view text, const std::string& source, const ColumnMap& map);

}  // namespace trueaxis::measure
