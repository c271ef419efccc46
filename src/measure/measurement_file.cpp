#include "trueaxis/measure/measurement_file.hpp"

#include <algorithm>
#include <cctype>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/ecmc_dat.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace trueaxis::measure {

MeasurementFormat DetectMeasurementFormat(const std::string& path, std::string_view text) {
  auto head = text.substr(0, std::min<std::size_t>(text.size(), 1 << 16));
  if (head.rfind("TEST_DATA=", 0) == 0 || head.find("TGT_DATA[") != std::string_view::npos ||
      head.find("REF_DATA_FWD[") != std::string_view::npos || head.find("REF_DATA_BWD[") != std::string_view::npos)
    return MeasurementFormat::kEcmcDat;
  std::string ext;
  if (auto dot = path.rfind('.'); dot != std::string::npos && path.find('/', dot) == std::string::npos)
    for (char c : path.substr(dot + 1)) ext += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "dat") return MeasurementFormat::kEcmcDat;
  return MeasurementFormat::kCanonicalCsv;
}

const char* MeasurementFormatName(MeasurementFormat f) {
  return f == MeasurementFormat::kEcmcDat ? "ecmc .dat" : "canonical CSV";
}

Measurement ParseMeasurement(std::string_view text, const std::string& source, MeasurementFormat format) {
  return format == MeasurementFormat::kEcmcDat ? ParseEcmcDat(text, source) : ParseMeasurementCsv(text, source);
}

Measurement ReadMeasurementFile(const std::string& path) {
  const auto text = ReadTextFile(path);
  return ParseMeasurement(text, path, DetectMeasurementFormat(path, text));
}

}  // namespace trueaxis::measure
