#pragma once
// Register-level conversions shared by the MODBUS server and clients: pure,
// allocation-free, and tested on their own (tests/drivers/register_codec_test.cpp).
#include <cstdint>

#include "trueaxis/drivers/adam6015_map.hpp"

namespace trueaxis::drivers {

// ---- 32-bit values over two registers, high word first ----
inline constexpr void SplitInt32(std::int32_t value, std::uint16_t* hi_lo) {
  const auto u = static_cast<std::uint32_t>(value);
  hi_lo[0] = static_cast<std::uint16_t>(u >> 16);
  hi_lo[1] = static_cast<std::uint16_t>(u & 0xFFFFu);
}
inline constexpr std::int32_t JoinInt32(const std::uint16_t* hi_lo) {
  return static_cast<std::int32_t>((static_cast<std::uint32_t>(hi_lo[0]) << 16) | hi_lo[1]);
}
inline constexpr std::uint32_t JoinUint32(const std::uint16_t* hi_lo) {
  return (static_cast<std::uint32_t>(hi_lo[0]) << 16) | hi_lo[1];
}

// ---- Fixed point lengths: int32 counts of 0.1 µm ----
inline constexpr double kLengthQuantumUm = 0.1;

// Rounds to the nearest 0.1 µm. False (and *counts saturated at the int32
// limit) when |um| is beyond ±214.7 m or not a number (NaN gives 0).
bool MicrometresToCounts(double um, std::int32_t* counts);
inline constexpr double CountsToMicrometres(std::int32_t counts) { return counts * kLengthQuantumUm; }
inline bool MillimetresToCounts(double mm, std::int32_t* counts) { return MicrometresToCounts(mm * 1000.0, counts); }
inline constexpr double CountsToMillimetres(std::int32_t counts) { return counts * kLengthQuantumUm / 1000.0; }

// ---- ADAM-6015 RTD scaling: raw 0..65535 linear over [min_c, max_c] ----
const adam6015::RtdRange* FindRtdRange(std::uint16_t code);  // nullptr when unknown
double AdamRawToCelsius(std::uint16_t raw, const adam6015::RtdRange& range);
// Rounds to the nearest count and clamps below the range to 0 and above it to
// 65535 (= kBurnoutRaw: over range reads like burn-out, as on the module).
std::uint16_t CelsiusToAdamRaw(double temp_c, const adam6015::RtdRange& range);
// One count in °C for the range (the module's resolution).
double AdamResolutionC(const adam6015::RtdRange& range);

}  // namespace trueaxis::drivers
