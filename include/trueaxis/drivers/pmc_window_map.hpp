#pragma once
// The PMC window register map: how a CNC's PMC (the ladder's I/O window, the
// place a FANUC/Siemens/Mitsubishi integration puts an external compensator's
// signals) is laid out over MODBUS TCP by ModbusMachineServer and read by
// ModbusCncLink. One place, so server, client, docs/protocols.md and the tests
// cannot drift apart.
//
// Addresses are PDU addresses (0-based, what goes on the wire). The 1-based
// "reference" numbers mbpoll and most HMIs show are address + 1 (input
// register 30001 = address 0, holding register 40001 = address 0).
//
// 32-bit values occupy two consecutive registers, HIGH word first (big-endian
// word order, "ABCD", the MODBUS convention for multi-register values; mbpoll
// needs -B to show them as int). Lengths are in units of 0.1 µm so a µm
// figure survives the trip with one decimal and ±214 m fit in an int32.
#include <cstddef>
#include <cstdint>

namespace trueaxis::drivers::pmc {

inline constexpr int kDefaultUnitId = 1;       // the CNC's PMC window
inline constexpr std::uint16_t kLayoutVersion = 1;
inline constexpr std::size_t kMaxAxes = 8;

// ---- Input registers (FC 04, read-only): the CNC's state ----------------
inline constexpr int kIrLayoutVersion = 0;     // = kLayoutVersion
inline constexpr int kIrAxisCount = 1;         // number of axes in this window
inline constexpr int kIrHeartbeatHi = 2;       // uint32 machine-cycle counter, +1 per server
inline constexpr int kIrHeartbeatLo = 3;       //   machine exchange; frozen = stale link
inline constexpr int kIrCoolant = 4;           // CoolantState code 0 off, 1 flood, 2 mist, 3 air
inline constexpr int kIrStatus = 5;            // bit field, kStatus*
inline constexpr int kIrReadAgeMs = 6;         // ms since the machine was last read OK (saturates 65535)
inline constexpr int kIrWriteCount = 7;        // uint16 count of compensation vectors forwarded to the CNC (wraps)
inline constexpr int kIrProgrammedDirection = 8;  // bits: bit a = axis a's programmed motion is towards +,
                                                  //   bit 8 + a = towards −; neither (a terminal that
                                                  //   does not know; older terminals read 0) = not known
inline constexpr int kIrAxisBase = 16;         // first per-axis block
inline constexpr int kIrAxisStride = 8;        // registers per axis
inline constexpr int kIrAxisPositionHi = 0;    // int32 machine position, 0.1 µm
inline constexpr int kIrAxisPositionLo = 1;
inline constexpr int kIrAxisDirection = 2;     // int16: +1 towards +, -1 towards -, 0 unknown
inline constexpr int kIrAxisMoving = 3;        // 0/1
inline constexpr int kIrAxisAppliedHi = 4;     // int32 compensation the CNC applies now, 0.1 µm
inline constexpr int kIrAxisAppliedLo = 5;
inline constexpr int kIrAxisTravelHi = 6;      // uint32 path travelled since the terminal started, mm
inline constexpr int kIrAxisTravelLo = 7;      //   (the CNC's distance counter, or summed by the terminal)
inline constexpr int kInputRegisterCount = kIrAxisBase + kIrAxisStride * static_cast<int>(kMaxAxes);

inline constexpr std::uint16_t kStatusCompensationEnabled = 1u << 0;  // effective CNC-side enable
inline constexpr std::uint16_t kStatusMachineReadOk = 1u << 1;        // last CncLink::Read succeeded
inline constexpr std::uint16_t kStatusLastWriteOk = 1u << 2;          // last WriteCompensation succeeded
inline constexpr std::uint16_t kStatusTemperatureReadOk = 1u << 3;    // last TemperatureSource::Read succeeded
inline constexpr std::uint16_t kStatusWatchdogRamping = 1u << 4;      // no client write for watchdog_s: ramping to 0

// ---- Holding registers (FC 03 read, FC 06/16 write): the compensator's inputs ----
inline constexpr int kHrEnable = 0;            // PMC enable bit, 0/1 (anded with the CNC's own enable)
inline constexpr int kHrCompensationBase = 16; // per axis: int32 correction, 0.1 µm, hi word first
inline constexpr int kHrCompensationStride = 2;
inline constexpr int kHoldingRegisterCount = kHrCompensationBase + kHrCompensationStride * static_cast<int>(kMaxAxes);
// Holding registers 100… (read-only): a copy of the input window, refreshed with it, so that one
// FC 23 (read/write multiple registers) writes the command block and reads the CNC's state.
inline constexpr int kHrWindowCopyBase = 100;
inline constexpr int kHoldingImageCount = kHrWindowCopyBase + kInputRegisterCount;

// Axis `axis`'s bits of the programmed-direction register for `direction` (+1, −1; 0: none).
inline constexpr std::uint16_t ProgrammedDirectionBits(std::size_t axis, int direction) {
  return direction > 0 ? static_cast<std::uint16_t>(1u << axis)
         : direction < 0 ? static_cast<std::uint16_t>(1u << (8 + axis))
                         : std::uint16_t{0};
}
// Axis `axis`'s programmed direction in the register's `bits`: +1, −1, or 0 (neither bit, or both:
// not known).
inline constexpr int ProgrammedDirection(std::uint16_t bits, std::size_t axis) {
  const bool plus = (bits >> axis) & 1u, minus = (bits >> (8 + axis)) & 1u;
  return plus == minus ? 0 : plus ? 1 : -1;
}
static_assert(kMaxAxes <= 8, "the programmed-direction register holds 8 axes");

inline constexpr int InputAxisRegister(std::size_t axis, int field) {
  return kIrAxisBase + kIrAxisStride * static_cast<int>(axis) + field;
}
inline constexpr int CompensationRegister(std::size_t axis) {
  return kHrCompensationBase + kHrCompensationStride * static_cast<int>(axis);
}
// Registers a client reads to get the whole window for `axis_count` axes.
inline constexpr int InputWindowLength(std::size_t axis_count) {
  return kIrAxisBase + kIrAxisStride * static_cast<int>(axis_count);
}

}  // namespace trueaxis::drivers::pmc
