#pragma once
// Advantech ADAM-6015 (7-channel isolated RTD input module, MODBUS TCP) register
// map, the parts ModbusMachineServer reproduces and ModbusTemperatureSource reads.
// Source: ADAM-6000 Series User Manual, appendix B (MODBUS address table of the
// ADAM-6015), and the RTD input-range (type) codes of the ADAM-4015/6015
// (ADAM-4000 manual table 5.2). What is and is not reproduced: docs/protocols.md.
//
// Reference numbers as in the manual (0X = coils, 4X = holding registers);
// the *Address constants are the 0-based PDU addresses on the wire.
#include <array>
#include <cstdint>
#include <string_view>

namespace trueaxis::drivers::adam6015 {

inline constexpr int kChannelCount = 7;

// 4X registers (FC 03; the ADAM also answers FC 04 at the same addresses).
inline constexpr int kAiValueAddress = 0;        // 40001..40007 raw 0..65535 over the range
inline constexpr int kAiMaxAddress = 10;         // 40011..40017 historical maximum, raw
inline constexpr int kAiMinAddress = 20;         // 40021..40027 historical minimum, raw
inline constexpr int kTypeCodeAddress = 200;     // 40201..40207 input range (type) code, R/W
inline constexpr int kModuleNameAddress = 210;   // 40211..40212 module name 0x6015, 0x0000
inline constexpr int kChannelEnableAddress = 220;// 40221 channel enable bit mask (bit i = channel i)
inline constexpr int kRegisterCount = 221;

// 0X coils (FC 01 read, FC 05/15 write).
inline constexpr int kResetMaxCoilAddress = 100; // 00101..00107 write 1: reset historical max
inline constexpr int kResetMinCoilAddress = 110; // 00111..00117 write 1: reset historical min
inline constexpr int kBurnoutCoilAddress = 120;  // 00121..00127 burn-out flag (open RTD), read-only
inline constexpr int kCoilCount = 127;

inline constexpr std::uint16_t kModuleName = 0x6015;
// An open (burnt-out) RTD, or a reading beyond the top of the range, reads as
// full scale; the burn-out coil tells the two apart.
inline constexpr std::uint16_t kBurnoutRaw = 0xFFFF;

struct RtdRange {
  std::uint16_t code;
  std::string_view name;
  double min_c;
  double max_c;
};

// Type codes 0x20..0x2D (IEC: α = 0.00385, JIS: α = 0.00391) of the original
// firmware (shared with the ADAM-4015), and the 16-bit codes of the ADAM-6000
// manual edition 9 (firmware >= 5) for the ranges they could be checked for.
inline constexpr std::array<RtdRange, 20> kRtdRanges = {{
    {0x20, "Pt100 (IEC) -50~150 C", -50.0, 150.0},
    {0x21, "Pt100 (IEC) 0~100 C", 0.0, 100.0},
    {0x22, "Pt100 (IEC) 0~200 C", 0.0, 200.0},
    {0x23, "Pt100 (IEC) 0~400 C", 0.0, 400.0},
    {0x24, "Pt100 (IEC) -200~200 C", -200.0, 200.0},
    {0x25, "Pt100 (JIS) -50~150 C", -50.0, 150.0},
    {0x26, "Pt100 (JIS) 0~100 C", 0.0, 100.0},
    {0x27, "Pt100 (JIS) 0~200 C", 0.0, 200.0},
    {0x28, "Pt100 (JIS) 0~400 C", 0.0, 400.0},
    {0x29, "Pt100 (JIS) -200~200 C", -200.0, 200.0},
    {0x2A, "Pt1000 -40~160 C", -40.0, 160.0},
    {0x2B, "BALCO500 -30~120 C", -30.0, 120.0},
    {0x2C, "Ni604 -80~100 C", -80.0, 100.0},
    {0x2D, "Ni604 0~100 C", 0.0, 100.0},
    {0x03A4, "Pt100 (385) -50~150 C", -50.0, 150.0},
    {0x03A5, "Pt100 (385) 0~100 C", 0.0, 100.0},
    {0x03A6, "Pt100 (385) 0~200 C", 0.0, 200.0},
    {0x03A7, "Pt100 (385) 0~400 C", 0.0, 400.0},
    {0x03A2, "Pt100 (385) -200~200 C", -200.0, 200.0},
    {0x03C4, "Pt100 (392) -50~150 C", -50.0, 150.0},
}};
inline constexpr std::uint16_t kDefaultRangeCode = 0x20;  // Pt100 -50~150 °C: 0.0031 °C per count

}  // namespace trueaxis::drivers::adam6015
