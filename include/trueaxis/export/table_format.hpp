#pragma once
// The controller table formats trueaxis writes and reads (docs/export.md),
// with the per-format limits the resampler must respect.
#include <optional>
#include <string>
#include <string_view>

namespace trueaxis::exporter {

enum class TableFormat { kLinuxCnc, kSinumerik, kFanuc, kHeidenhain, kCsv };

std::optional<TableFormat> ParseTableFormat(std::string_view name);
std::string_view TableFormatName(TableFormat f);

// Default point limit of one table (checked; --max-points may lower or, where
// the controller is configurable, raise it — docs/export.md gives the source).
int DefaultMaxPoints(TableFormat f);

// Whether the format holds separate forward and reverse curves.
bool SupportsBidirectional(TableFormat f);

}  // namespace trueaxis::exporter
