#include "trueaxis/measure/measurement_file.hpp"

#include <algorithm>
#include <cctype>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/measure/ecmc_dat.hpp"
#include "trueaxis/measure/mapped_csv.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace trueaxis::measure {
namespace {

// Whether the CSV's header line names the canonical columns run, direction, target_mm, deviation_um.
bool HasCanonicalHeader(std::string_view text) {
  const std::string canonical = CanonicalCsv(text);
  LineCursor cursor(canonical);
  while (cursor.Next()) {
    const auto line = cursor.line();
    if (line.empty() || line.front() == '#') continue;
    const auto fields = SplitCsvFields(line);
    static constexpr std::string_view kRequired[] = {"run", "direction", "target_mm", "deviation_um"};
    return std::all_of(std::begin(kRequired), std::end(kRequired), [&](std::string_view name) {
      return std::find(fields.begin(), fields.end(), name) != fields.end();
    });
  }
  return false;
}

}  // namespace

MeasurementFormat DetectMeasurementFormat(const std::string& path, std::string_view text,
                                          const MeasurementReadOptions& options) {
  auto head = text.substr(0, std::min<std::size_t>(text.size(), 1 << 16));
  if (head.rfind("TEST_DATA=", 0) == 0 || head.find("TGT_DATA[") != std::string_view::npos ||
      head.find("REF_DATA_FWD[") != std::string_view::npos || head.find("REF_DATA_BWD[") != std::string_view::npos)
    return MeasurementFormat::kEcmcDat;
  std::string ext;
  if (auto dot = path.rfind('.'); dot != std::string::npos && path.find('/', dot) == std::string::npos)
    for (char c : path.substr(dot + 1)) ext += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "dat") return MeasurementFormat::kEcmcDat;
  if (options.columns && !HasCanonicalHeader(text)) return MeasurementFormat::kMappedCsv;
  return MeasurementFormat::kCanonicalCsv;
}

const char* MeasurementFormatName(MeasurementFormat f) {
  switch (f) {
    case MeasurementFormat::kEcmcDat: return "ecmc .dat";
    case MeasurementFormat::kMappedCsv: return "mapped CSV";
    case MeasurementFormat::kCanonicalCsv: break;
  }
  return "canonical CSV";
}

Measurement ParseMeasurement(std::string_view text, const std::string& source, const MeasurementReadOptions& options) {
  switch (DetectMeasurementFormat(source, text, options)) {
    case MeasurementFormat::kEcmcDat: return ParseEcmcDat(text, source);
    case MeasurementFormat::kMappedCsv: return ParseMappedCsv(text, source, *options.columns);
    case MeasurementFormat::kCanonicalCsv: break;
  }
  return ParseMeasurementCsv(text, source);
}

Measurement ReadMeasurementFile(const std::string& path, const MeasurementReadOptions& options) {
  return ParseMeasurement(ReadTextFile(path), path, options);
}

}  // namespace trueaxis::measure
