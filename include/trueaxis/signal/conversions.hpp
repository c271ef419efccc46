#pragma once
// Hardware conversions of temperature readings (MISSION M2, seed 000
// "温度实时监测单元"): pure functions, no state, no allocation.
//
// 1. Analog chain (seed 000): Pt100 -> isolated transmitter (0-50 °C -> 0-5 V,
//    linear) -> 12-bit ADC card (PCI-1711 class). A count is converted to
//    volts by the ADC's input range, volts to °C by the transmitter's span.
//    Readings pinned at an ADC rail, or far outside the transmitter's span,
//    are flagged as a hardware fault: a burnt-out / open RTD drives an
//    up-scale transmitter to its top rail, a shorted RTD or a dead loop reads
//    at or below the bottom of the span.
// 2. DS18B20 digital sensor: signed 16-bit two's complement, 1/16 °C per LSB
//    at 12-bit resolution (lower bits undefined at 9-11 bits). 0x0550 is
//    85 °C, the power-on reset value of the scratchpad: read before a
//    conversion finished (or after a brown-out) it looks like a real reading,
//    so it is treated as suspicious unless explicitly allowed.
#include <cstdint>
#include <string>

#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::signal {

// Where a converted reading sits relative to what the hardware can deliver.
enum class ConversionCondition {
  kOk,
  kBelowSpan,   // below the transmitter span by more than the margin: short circuit / dead loop
  kAboveSpan,   // above the span by more than the margin: open circuit (up-scale burn-out)
  kAtAdcRail,   // ADC count at 0 or full scale: the input is saturated, the value means nothing
  kSuspicious,  // DS18B20 power-on value 0x0550 (85 °C)
  kInvalid,     // bit pattern outside the device's documented range
};
std::string_view ConversionConditionName(ConversionCondition c);

struct AnalogChannelOptions {
  int adc_bits = 12;            // PCI-1711: 12 bit
  double adc_min_v = 0.0;       // ADC input range (voltage at count 0)
  double adc_max_v = 5.0;       // voltage at the full-scale count 2^bits - 1
  double span_min_c = 0.0;      // transmitter: temperature at output span_min_v
  double span_max_c = 50.0;     // temperature at output span_max_v
  double span_min_v = 0.0;
  double span_max_v = 5.0;
  double fault_margin_c = 1.0;  // tolerated excursion beyond the span before it is a fault
  // True when a count at 0 or full scale means "saturated" (fault). Switch off
  // when the ADC range equals the span exactly and the rails are legitimate
  // span ends (then only the margin check applies).
  bool rails_are_faults = true;

  bool IsValid(std::string* why) const;
  int FullScaleCount() const { return (1 << adc_bits) - 1; }
};

double AdcCountToVolts(int count, const AnalogChannelOptions& o);
// Nearest count for a voltage, clamped to [0, full scale].
int VoltsToAdcCount(double volts, const AnalogChannelOptions& o);
double TransmitterVoltsToCelsius(double volts, const AnalogChannelOptions& o);
double CelsiusToTransmitterVolts(double temp_c, const AnalogChannelOptions& o);
// One ADC step expressed in °C (0.0122 °C for the 0-50 °C / 0-5 V / 12-bit chain).
double AnalogResolutionC(const AnalogChannelOptions& o);

struct ConvertedReading {
  double temp_c = 0;
  ConversionCondition condition = ConversionCondition::kOk;
  hw::RawTemperature ToRaw() const { return {temp_c, condition != ConversionCondition::kOk}; }
};

ConvertedReading ConvertAdcCount(int count, const AnalogChannelOptions& o);

// ---- DS18B20 ----
inline constexpr std::uint16_t kDs18b20PowerOnRaw = 0x0550;  // +85 °C
inline constexpr double kDs18b20LsbC = 0.0625;

struct Ds18b20Options {
  int resolution_bits = 12;            // 9..12; undefined low bits are masked off
  bool power_on_value_is_fault = true; // 0x0550 (85 °C) treated as suspicious
  bool IsValid(std::string* why) const;
};

double Ds18b20RawToCelsius(std::uint16_t raw, const Ds18b20Options& o = {});
// Nearest representable raw value at the given resolution, clamped to -55..+125 °C.
std::uint16_t CelsiusToDs18b20Raw(double temp_c, const Ds18b20Options& o = {});
ConvertedReading ConvertDs18b20(std::uint16_t raw, const Ds18b20Options& o = {});

}  // namespace trueaxis::signal
