#include "trueaxis/signal/conversions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace trueaxis::signal {

std::string_view ConversionConditionName(ConversionCondition c) {
  switch (c) {
    case ConversionCondition::kOk: return "ok";
    case ConversionCondition::kBelowSpan: return "below_span";
    case ConversionCondition::kAboveSpan: return "above_span";
    case ConversionCondition::kAtAdcRail: return "at_adc_rail";
    case ConversionCondition::kSuspicious: return "suspicious";
    case ConversionCondition::kInvalid: return "invalid";
  }
  return "unknown";
}

bool AnalogChannelOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (adc_bits < 8 || adc_bits > 24) return fail(fmt::format("adc_bits must be 8..24, got {}", adc_bits));
  if (!(adc_max_v > adc_min_v)) return fail("adc_max_v must be greater than adc_min_v");
  if (!(span_max_v != span_min_v)) return fail("span_min_v and span_max_v must differ");
  if (!(span_max_c > span_min_c)) return fail("span_max_c must be greater than span_min_c");
  if (!(fault_margin_c >= 0)) return fail("fault_margin_c must be >= 0");
  if (!std::isfinite(adc_min_v + adc_max_v + span_min_v + span_max_v + span_min_c + span_max_c))
    return fail("ranges must be finite");
  return true;
}

double AdcCountToVolts(int count, const AnalogChannelOptions& o) {
  return o.adc_min_v + (o.adc_max_v - o.adc_min_v) * static_cast<double>(count) / o.FullScaleCount();
}

int VoltsToAdcCount(double volts, const AnalogChannelOptions& o) {
  const double c = std::round((volts - o.adc_min_v) / (o.adc_max_v - o.adc_min_v) * o.FullScaleCount());
  if (!(c >= 0)) return 0;  // also NaN
  return static_cast<int>(std::min<double>(c, o.FullScaleCount()));
}

double TransmitterVoltsToCelsius(double volts, const AnalogChannelOptions& o) {
  return o.span_min_c + (volts - o.span_min_v) * (o.span_max_c - o.span_min_c) / (o.span_max_v - o.span_min_v);
}

double CelsiusToTransmitterVolts(double temp_c, const AnalogChannelOptions& o) {
  return o.span_min_v + (temp_c - o.span_min_c) * (o.span_max_v - o.span_min_v) / (o.span_max_c - o.span_min_c);
}

double AnalogResolutionC(const AnalogChannelOptions& o) {
  const double volts_per_count = (o.adc_max_v - o.adc_min_v) / o.FullScaleCount();
  return std::abs(volts_per_count * (o.span_max_c - o.span_min_c) / (o.span_max_v - o.span_min_v));
}

ConvertedReading ConvertAdcCount(int count, const AnalogChannelOptions& o) {
  ConvertedReading r;
  r.temp_c = TransmitterVoltsToCelsius(AdcCountToVolts(count, o), o);
  if (count < 0 || count > o.FullScaleCount()) {
    r.condition = ConversionCondition::kInvalid;
  } else if (o.rails_are_faults && (count == 0 || count == o.FullScaleCount())) {
    r.condition = ConversionCondition::kAtAdcRail;
  } else if (r.temp_c < o.span_min_c - o.fault_margin_c) {
    r.condition = ConversionCondition::kBelowSpan;
  } else if (r.temp_c > o.span_max_c + o.fault_margin_c) {
    r.condition = ConversionCondition::kAboveSpan;
  }
  return r;
}

bool Ds18b20Options::IsValid(std::string* why) const {
  if (resolution_bits < 9 || resolution_bits > 12) {
    if (why) *why = fmt::format("resolution_bits must be 9..12, got {}", resolution_bits);
    return false;
  }
  return true;
}

namespace {
std::uint16_t ResolutionMask(const Ds18b20Options& o) {
  // 12 bit: all bits valid; each bit less leaves one more undefined LSB.
  return static_cast<std::uint16_t>(0xFFFFu << (12 - o.resolution_bits));
}
}  // namespace

double Ds18b20RawToCelsius(std::uint16_t raw, const Ds18b20Options& o) {
  const auto masked = static_cast<std::int16_t>(raw & ResolutionMask(o));
  return masked * kDs18b20LsbC;
}

std::uint16_t CelsiusToDs18b20Raw(double temp_c, const Ds18b20Options& o) {
  const double clamped = std::clamp(temp_c, -55.0, 125.0);
  const double step = kDs18b20LsbC * (1 << (12 - o.resolution_bits));
  const auto lsbs = static_cast<long>(std::lround(clamped / step)) * (1L << (12 - o.resolution_bits));
  return static_cast<std::uint16_t>(static_cast<std::int16_t>(lsbs));
}

ConvertedReading ConvertDs18b20(std::uint16_t raw, const Ds18b20Options& o) {
  ConvertedReading r;
  r.temp_c = Ds18b20RawToCelsius(raw, o);
  const auto value = static_cast<std::int16_t>(raw);
  // Documented range -55..+125 °C; the top 5 bits are sign extension, so a
  // pattern outside the range is a bus error, not a temperature.
  if (value < -55 * 16 || value > 125 * 16) {
    r.condition = ConversionCondition::kInvalid;
  } else if (raw == kDs18b20PowerOnRaw && o.power_on_value_is_fault) {
    r.condition = ConversionCondition::kSuspicious;
  }
  return r;
}

}  // namespace trueaxis::signal
