#pragma once
// The text of a DS18B20's `w1_slave` file in the Linux 1-Wire sysfs interface
// (drivers/w1/slaves/w1_therm.c), e.g.
//
//   72 01 4b 46 7f ff 0e 10 57 : crc=57 YES
//   72 01 4b 46 7f ff 0e 10 57 t=23125
//
// Line 1: the 9 scratchpad bytes, the CRC the kernel computed, YES/NO = CRC
// check passed. Line 2: the same bytes and the temperature in milli-°C.
// Pure parsing: no files, no policy on the 85 °C power-on value (that needs
// the channel's history: OneWireTemperatureSource).
#include <string>
#include <string_view>

#include "trueaxis/signal/conversions.hpp"

namespace trueaxis::terminal {

enum class W1SlaveStatus {
  kOk,          // CRC YES and a temperature
  kCrcError,    // CRC NO: the bytes were corrupted on the wire (a failed read)
  kNoResponse,  // all scratchpad bytes 0x00 (the kernel says YES: CRC of zeros is 0) = nobody answered
  kMalformed,   // not the two-line format (empty, truncated, garbage)
};

struct W1SlaveReading {
  W1SlaveStatus status = W1SlaveStatus::kMalformed;
  long milli_c = 0;     // valid when status == kOk
  std::string why;      // for kMalformed: what was wrong
};

W1SlaveReading ParseW1Slave(std::string_view text);
const char* W1SlaveStatusName(W1SlaveStatus status);

// DS18B20 facts (datasheet): measuring range and the power-on reset value of
// the temperature register (+85 °C), which a sensor reports when it lost power
// between the conversion command and the read.
inline constexpr long kDs18b20PowerOnMilliC = static_cast<long>(signal::kDs18b20PowerOnRaw * signal::kDs18b20LsbC * 1000);  // 85000
static_assert(kDs18b20PowerOnMilliC == 85000);
inline constexpr double kDs18b20MinC = -55.0;
inline constexpr double kDs18b20MaxC = 125.0;
inline constexpr double kDs18b20ConversionS = 0.75;  // max conversion time at 12 bits (datasheet: 750 ms)

}  // namespace trueaxis::terminal
