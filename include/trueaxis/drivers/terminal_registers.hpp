#pragma once
// The terminal register model: what a machine's MODBUS terminal holds and how its state becomes
// registers and registers become state again — one place for both terminal servers
// (ModbusMachineServer of `sim serve` / `terminal`, the virtual shop of `sim shop`) and both
// clients (ModbusCncLink + ModbusTemperatureSource over libmodbus, the workshop server's own
// MBAP client). The addresses are pmc_window_map.hpp and adam6015_map.hpp; every register is
// listed in docs/protocols.md.
//
//   PMC window (unit pmc_unit_id)
//     input registers     EncodePmcState / EncodeWriteResult   →  DecodePmcWindow
//     holding registers   EncodeCommand (the command block a client writes)
//                         CheckPmcWrite (what a terminal accepts) → DecodeCommand
//                         RampCommandToZero (the watchdog: no client write for a while)
//   ADAM-6015 modules (units first_rtd_unit_id + k)
//     holding registers   InitRtdModule / EncodeRtdChannel     →  DecodeRtdChannel
//                         CheckRtdTypeCodeWrite, ResetRtdHistory
//
// Pure, allocation-free functions over register arrays (the servers keep their images in their
// own storage: libmodbus mappings, plain arrays); unit-tested on their own
// (tests/drivers/terminal_registers_test.cpp).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/pmc_window_map.hpp"
#include "trueaxis/drivers/register_codec.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::drivers {

// ---------------------------------------------------------------- the map
// Holding registers a terminal with `axis_count` axes serves (enable + its command block).
inline constexpr int PmcHoldingLength(std::size_t axis_count) {
  return pmc::kHrCompensationBase + pmc::kHrCompensationStride * static_cast<int>(axis_count);
}
// Holding registers a terminal answers reads of: enable, command block, reserved, and the
// read-only copy of the input window from pmc::kHrWindowCopyBase (the read part of an FC 23).
inline constexpr int PmcHoldingImageLength(std::size_t axis_count) {
  return pmc::kHrWindowCopyBase + pmc::InputWindowLength(axis_count);
}
// Registers of the command block (2 per axis), written from pmc::kHrCompensationBase.
inline constexpr int CommandBlockLength(std::size_t axis_count) {
  return pmc::kHrCompensationStride * static_cast<int>(axis_count);
}
// Channels module `module` holds when the terminal has `channel_count` channels.
inline constexpr std::size_t RtdModuleChannels(std::size_t channel_count, std::size_t module) {
  const std::size_t first = module * adam6015::kChannelCount;
  return first >= channel_count ? 0
         : channel_count - first < adam6015::kChannelCount ? channel_count - first
                                                           : adam6015::kChannelCount;
}
inline constexpr std::size_t RtdModulesFor(std::size_t channel_count) {
  return (channel_count + adam6015::kChannelCount - 1) / adam6015::kChannelCount;
}

// ---------------------------------------------------------------- PMC window, terminal side
// The fixed head (layout version, axis count) and the start value of the enable register.
// `ir` holds pmc::InputWindowLength(axis_count) registers, `hr` PmcHoldingImageLength(axis_count).
void InitPmcImage(std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count, bool enable);
// Refreshes the holding registers' copy of the input window: a terminal calls it whenever it has
// changed the input registers (after EncodePmcState, EncodeWriteResult, CommandWatchdog::Step).
void CopyWindowToHolding(const std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count);

// One machine exchange's state as the terminal publishes it.
struct PmcExchange {
  std::uint32_t heartbeat = 0;
  bool machine_read_ok = false;      // the CNC answered: `machine` and `axes` are this exchange's
  bool temperatures_read_ok = false;
  hw::CncState machine;
  std::span<const hw::AxisState> axes;
  std::span<const double> travel_mm;  // per axis: the terminal's travelled path (floored, saturated)
  double read_age_ms = 0;             // since the CNC was last read OK (saturates at 65535)
};
// Writes heartbeat, status (keeps the last-write bit; the watchdog bit is cleared, RampCommandToZero
// sets it again), age and — when the CNC was read — coolant, effective enable (the CNC's AND
// holding register 0), programmed directions and each axis's position, direction, moving flag
// and travel. When it was not read, the last good state stays on the registers.
void EncodePmcState(const PmcExchange& exchange, std::uint16_t* ir, const std::uint16_t* hr);
// After the terminal handed a command to its CNC: the last-write status bit, and when the CNC
// accepted it the write count and the applied values.
void EncodeWriteResult(bool ok, std::span<const double> applied_um, std::uint16_t* ir);

// Each axis's travelled path as the terminal publishes it: the CNC's own distance counter when it
// reports one, else summed from the position change of each good read since the terminal started.
class TravelCounter {
 public:
  explicit TravelCounter(std::size_t axis_count = 0) : travel_mm_(axis_count, 0.0), last_position_mm_(axis_count, 0.0) {}
  // After a good read of every axis.
  void Update(std::span<const hw::AxisState> axes);
  std::span<const double> travel_mm() const { return travel_mm_; }

 private:
  std::vector<double> travel_mm_, last_position_mm_;
  bool ever_read_ = false;
};

// ---------------------------------------------------------------- PMC window, client side
// The window's head and the decoded state, as a client reads it.
struct PmcWindow {
  std::uint16_t layout_version = 0;
  std::uint16_t axis_count = 0;
  std::uint32_t heartbeat = 0;
  std::uint16_t status = 0;
  std::uint16_t read_age_ms = 0;
  std::uint16_t write_count = 0;
  bool coolant_known = false;  // the coolant code is one of the four states
  bool machine_read_ok() const { return (status & pmc::kStatusMachineReadOk) != 0; }
  bool watchdog_ramping() const { return (status & pmc::kStatusWatchdogRamping) != 0; }
};
// True when the head names this layout and `axis_count` axes.
bool PmcLayoutMatches(const std::uint16_t* ir, std::size_t axis_count);
// Decodes a window of pmc::InputWindowLength(axes.size()) registers: every axis's state and
// applied compensation (`applied_um` may be empty), the machine state and the head.
PmcWindow DecodePmcWindow(const std::uint16_t* ir, std::span<hw::AxisState> axes, hw::CncState& machine,
                          std::span<double> applied_um);

// When the heartbeat last moved: a terminal that answers but whose machine side has stopped.
struct HeartbeatWatch {
  std::uint32_t heartbeat = 0;
  bool seen = false;
  double changed_at_s = 0;
  // Notes `heartbeat` at `now_s`; true while it has moved within `stale_after_s`.
  bool Fresh(std::uint32_t value, double now_s, double stale_after_s);
  void Reset() { seen = false; }
};

// ---------------------------------------------------------------- the command block
// One correction per axis (µm, correction sign) into CommandBlockLength registers. False (block
// untouched from the bad axis on) when a value is NaN or beyond the int32 counts: never sent.
bool EncodeCommand(std::span<const double> correction_um, std::uint16_t* block);
// The corrections (µm) in a block.
void DecodeCommand(const std::uint16_t* block, std::span<double> correction_um);
// A client's write of `count` registers from `address` into the holding registers `hr` of a
// terminal with `axis_count` axes: 0 when it may be applied (then `candidate` holds the image
// after it), else the MODBUS exception code — 0x02 for an address outside enable + command block,
// 0x03 for an enable other than 0/1 or an axis beyond ±max_abs_um. `value` gives the i-th word.
template <class ValueAt>
int CheckPmcWrite(const std::uint16_t* hr, std::size_t axis_count, int address, int count, ValueAt value,
                  double max_abs_um, std::uint16_t* candidate);

// The watchdog ramp: every axis's command moves towards 0 by max(1 count, ramp_um_per_s ·
// elapsed_s), never past it. True when it changed a value (the terminal then forwards the new
// command and sets status bit 4 with MarkWatchdogRamping).
bool RampCommandToZero(std::uint16_t* block, std::size_t axis_count, double ramp_um_per_s, double elapsed_s);
inline void MarkWatchdogRamping(std::uint16_t* ir) { ir[pmc::kIrStatus] |= pmc::kStatusWatchdogRamping; }

// The terminal's watchdog: when no client has written for timeout_s (> 0), ramp the command
// block to 0 at ramp_um_per_s. 0 = hold the last command. Both servers run this one.
struct CommandWatchdog {
  double timeout_s = 0;
  double ramp_um_per_s = 10;
  // True when it ramped (status bit 4 set in `ir`, the command block in `hr` changed).
  bool Step(std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count, double since_client_write_s,
            double elapsed_s) const;
};

// ---------------------------------------------------------------- ADAM-6015 modules
// A module's register image at start: type codes, name, channel-enable mask.
void InitRtdModule(std::uint16_t* registers, std::size_t channels, std::uint16_t range_code);
// Channel `c`'s reading into the module: value (burn-out/over range 0xFFFF), burn-out coil, and the
// historical max/min (restarted when !*history_valid). `coils` holds adam6015::kCoilCount bits.
void EncodeRtdChannel(const hw::RawTemperature& reading, const adam6015::RtdRange& range, std::size_t c,
                      std::uint16_t* registers, std::uint8_t* coils, bool* history_valid);
// A client's reading of a channel: the module's value in °C and the fault flag (burn-out coil, or
// the value at 0xFFFF).
hw::RawTemperature DecodeRtdChannel(std::uint16_t raw, bool burnout, const adam6015::RtdRange& range);
// A write of `count` type-code registers from `address` into a module with `channels` channels:
// 0 or the exception code (0x02 outside the type codes, 0x03 an unknown code).
template <class ValueAt>
int CheckRtdTypeCodeWrite(std::size_t channels, int address, int count, ValueAt value);
// A write of reset coils (`count` from `address`): 0, or 0x02 outside the reset coils.
int CheckRtdCoilWrite(std::size_t channels, int address, int count);
// After reset coils were written: max/min of the channels whose coils are set restart at the
// present value; the coils read 0 again.
void ResetRtdHistory(std::size_t channels, std::uint16_t* registers, std::uint8_t* coils);

// ---------------------------------------------------------------- templates
inline constexpr int kExceptionIllegalDataAddress = 2;
inline constexpr int kExceptionIllegalDataValue = 3;
bool PmcCommandWithinBound(const std::uint16_t* hr, std::size_t axis_count, double max_abs_um);

template <class ValueAt>
int CheckPmcWrite(const std::uint16_t* hr, std::size_t axis_count, int address, int count, ValueAt value,
                  double max_abs_um, std::uint16_t* candidate) {
  const int length = PmcHoldingLength(axis_count);
  for (int i = 0; i < length; ++i) candidate[i] = hr[i];
  for (int i = 0; i < count; ++i) {
    const int a = address + i;
    if (!(a == pmc::kHrEnable || (a >= pmc::kHrCompensationBase && a < length))) return kExceptionIllegalDataAddress;
    candidate[a] = value(i);
  }
  if (candidate[pmc::kHrEnable] > 1) return kExceptionIllegalDataValue;
  if (!PmcCommandWithinBound(candidate, axis_count, max_abs_um)) return kExceptionIllegalDataValue;
  return 0;
}

template <class ValueAt>
int CheckRtdTypeCodeWrite(std::size_t channels, int address, int count, ValueAt value) {
  for (int i = 0; i < count; ++i) {
    const int a = address + i;
    if (a < adam6015::kTypeCodeAddress || a >= adam6015::kTypeCodeAddress + static_cast<int>(channels))
      return kExceptionIllegalDataAddress;  // only the type codes are writable
    if (!FindRtdRange(value(i))) return kExceptionIllegalDataValue;
  }
  return 0;
}

}  // namespace trueaxis::drivers
