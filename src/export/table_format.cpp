#include "trueaxis/export/table_format.hpp"

#include <array>

namespace trueaxis::exporter {

namespace {
constexpr std::array<std::string_view, 5> kNames = {"linuxcnc", "sinumerik", "fanuc", "heidenhain", "csv"};
}

std::optional<TableFormat> ParseTableFormat(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<TableFormat>(i);
  return std::nullopt;
}

std::string_view TableFormatName(TableFormat f) { return kNames[static_cast<std::size_t>(f)]; }

int DefaultMaxPoints(TableFormat f) {
  switch (f) {
    case TableFormat::kLinuxCnc: return 256;    // ini-config: "256 triplets per joint"
    case TableFormat::kSinumerik: return 2000;  // MD38000 is configurable; conservative default
    case TableFormat::kFanuc: return 1024;      // point numbers 0…1023 for all axes together
    case TableFormat::kHeidenhain: return 256;  // TNC: ".COM has more than 256 entries" is an error
    case TableFormat::kCsv: return 100000;
  }
  return 256;
}

bool SupportsBidirectional(TableFormat f) { return f != TableFormat::kSinumerik; }

}  // namespace trueaxis::exporter
