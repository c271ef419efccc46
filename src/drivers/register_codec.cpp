#include "trueaxis/drivers/register_codec.hpp"

#include <cmath>
#include <limits>

namespace trueaxis::drivers {

bool MicrometresToCounts(double um, std::int32_t* counts) {
  if (std::isnan(um)) {
    *counts = 0;
    return false;
  }
  const double c = std::round(um / kLengthQuantumUm);
  constexpr double kMax = std::numeric_limits<std::int32_t>::max();
  constexpr double kMin = std::numeric_limits<std::int32_t>::min();
  if (c > kMax) {
    *counts = std::numeric_limits<std::int32_t>::max();
    return false;
  }
  if (c < kMin) {
    *counts = std::numeric_limits<std::int32_t>::min();
    return false;
  }
  *counts = static_cast<std::int32_t>(c);
  return true;
}

const adam6015::RtdRange* FindRtdRange(std::uint16_t code) {
  for (const auto& r : adam6015::kRtdRanges)
    if (r.code == code) return &r;
  return nullptr;
}

double AdamRawToCelsius(std::uint16_t raw, const adam6015::RtdRange& range) {
  return range.min_c + (range.max_c - range.min_c) * (static_cast<double>(raw) / 65535.0);
}

std::uint16_t CelsiusToAdamRaw(double temp_c, const adam6015::RtdRange& range) {
  if (std::isnan(temp_c)) return adam6015::kBurnoutRaw;
  const double counts = std::round((temp_c - range.min_c) / (range.max_c - range.min_c) * 65535.0);
  if (counts <= 0) return 0;
  if (counts >= 65535.0) return 65535;
  return static_cast<std::uint16_t>(counts);
}

double AdamResolutionC(const adam6015::RtdRange& range) { return (range.max_c - range.min_c) / 65535.0; }

}  // namespace trueaxis::drivers
