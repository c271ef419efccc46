#pragma once
// The fields of one measurement point as every CSV reader of a measurement reads them (the
// canonical CSV and a mapped laser-software export): the same checks and the same messages.
// Each throws InputError(source, line, field, why); `field` is the column as the file names it.
#include <optional>
#include <string>
#include <string_view>

namespace trueaxis::measure::detail {

enum class Quantity { kTargetMm, kDeviationUm, kTimeS };

// A run number: an integer 1..100000.
int ReadRunField(std::string_view f, const std::string& source, int line, const std::string& field);
// A finite number times `scale` (to mm, µm or s), then checked for plausibility in that unit.
double ReadQuantityField(std::string_view f, Quantity q, const std::string& source, int line, const std::string& field,
                         double scale = 1.0);
// A temperature in °C; nullopt for an empty field (not read).
std::optional<double> ReadTemperatureField(std::string_view f, const std::string& source, int line,
                                           const std::string& field);

}  // namespace trueaxis::measure::detail
