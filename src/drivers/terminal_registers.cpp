#include "trueaxis/drivers/terminal_registers.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::drivers {

void InitPmcImage(std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count, bool enable) {
  std::fill(ir, ir + pmc::InputWindowLength(axis_count), std::uint16_t{0});
  std::fill(hr, hr + PmcHoldingImageLength(axis_count), std::uint16_t{0});
  ir[pmc::kIrLayoutVersion] = pmc::kLayoutVersion;
  ir[pmc::kIrAxisCount] = static_cast<std::uint16_t>(axis_count);
  hr[pmc::kHrEnable] = enable ? 1 : 0;
  CopyWindowToHolding(ir, hr, axis_count);
}

void CopyWindowToHolding(const std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count) {
  std::copy(ir, ir + pmc::InputWindowLength(axis_count), hr + pmc::kHrWindowCopyBase);
}

void EncodePmcState(const PmcExchange& e, std::uint16_t* ir, const std::uint16_t* hr) {
  ir[pmc::kIrHeartbeatHi] = static_cast<std::uint16_t>(e.heartbeat >> 16);
  ir[pmc::kIrHeartbeatLo] = static_cast<std::uint16_t>(e.heartbeat & 0xFFFF);
  std::uint16_t status = ir[pmc::kIrStatus] & pmc::kStatusLastWriteOk;
  if (e.machine_read_ok) {
    status |= pmc::kStatusMachineReadOk;
    ir[pmc::kIrCoolant] = static_cast<std::uint16_t>(static_cast<int>(e.machine.coolant));
    if (e.machine.compensation_enabled && hr[pmc::kHrEnable] == 1) status |= pmc::kStatusCompensationEnabled;
    std::uint16_t programmed = 0;
    for (std::size_t a = 0; a < e.axes.size(); ++a) {
      const hw::AxisState& s = e.axes[a];
      programmed |= pmc::ProgrammedDirectionBits(a, s.programmed_direction);
      std::int32_t c = 0;
      MillimetresToCounts(s.position_mm, &c);
      SplitInt32(c, ir + pmc::InputAxisRegister(a, pmc::kIrAxisPositionHi));
      ir[pmc::InputAxisRegister(a, pmc::kIrAxisDirection)] =
          static_cast<std::uint16_t>(static_cast<std::int16_t>(std::clamp(s.servo_direction, -1, 1)));
      ir[pmc::InputAxisRegister(a, pmc::kIrAxisMoving)] = s.moving ? 1 : 0;
      const double travel = a < e.travel_mm.size() && std::isfinite(e.travel_mm[a])
                                ? std::clamp(std::floor(e.travel_mm[a]), 0.0, 4294967295.0)
                                : 0.0;
      const auto t = static_cast<std::uint32_t>(travel);
      ir[pmc::InputAxisRegister(a, pmc::kIrAxisTravelHi)] = static_cast<std::uint16_t>(t >> 16);
      ir[pmc::InputAxisRegister(a, pmc::kIrAxisTravelLo)] = static_cast<std::uint16_t>(t & 0xFFFF);
      // What the CNC applies, when it says (a terminal started while the CNC holds a value shows
      // that value, not its own zero); else the last value this terminal wrote stays.
      if (std::isfinite(s.applied_um) && MicrometresToCounts(s.applied_um, &c))
        SplitInt32(c, ir + pmc::InputAxisRegister(a, pmc::kIrAxisAppliedHi));
    }
    ir[pmc::kIrProgrammedDirection] = programmed;
  }
  // else: the last good state stays; the cleared bit and the growing age tell the client it is stale
  if (e.temperatures_read_ok) status |= pmc::kStatusTemperatureReadOk;
  ir[pmc::kIrStatus] = status;
  const double age = std::isfinite(e.read_age_ms) ? std::clamp(std::floor(e.read_age_ms), 0.0, 65535.0) : 65535.0;
  ir[pmc::kIrReadAgeMs] = static_cast<std::uint16_t>(age);
}

void TravelCounter::Update(std::span<const hw::AxisState> axes) {
  for (std::size_t a = 0; a < axes.size() && a < travel_mm_.size(); ++a) {
    if (std::isfinite(axes[a].travel_mm)) travel_mm_[a] = axes[a].travel_mm;
    else if (ever_read_) travel_mm_[a] += std::abs(axes[a].position_mm - last_position_mm_[a]);
    last_position_mm_[a] = axes[a].position_mm;
  }
  ever_read_ = true;
}

void EncodeWriteResult(bool ok, std::span<const double> applied_um, std::uint16_t* ir) {
  std::uint16_t& status = ir[pmc::kIrStatus];
  if (!ok) {
    status &= static_cast<std::uint16_t>(~pmc::kStatusLastWriteOk);
    return;
  }
  status |= pmc::kStatusLastWriteOk;
  ++ir[pmc::kIrWriteCount];
  for (std::size_t a = 0; a < applied_um.size(); ++a) {
    std::int32_t c = 0;
    MicrometresToCounts(applied_um[a], &c);
    SplitInt32(c, ir + pmc::InputAxisRegister(a, pmc::kIrAxisAppliedHi));
  }
}

bool PmcLayoutMatches(const std::uint16_t* ir, std::size_t axis_count) {
  return ir[pmc::kIrLayoutVersion] == pmc::kLayoutVersion && ir[pmc::kIrAxisCount] == axis_count;
}

PmcWindow DecodePmcWindow(const std::uint16_t* ir, std::span<hw::AxisState> axes, hw::CncState& machine,
                          std::span<double> applied_um) {
  PmcWindow w;
  w.layout_version = ir[pmc::kIrLayoutVersion];
  w.axis_count = ir[pmc::kIrAxisCount];
  w.heartbeat = JoinUint32(ir + pmc::kIrHeartbeatHi);
  w.status = ir[pmc::kIrStatus];
  w.read_age_ms = ir[pmc::kIrReadAgeMs];
  w.write_count = ir[pmc::kIrWriteCount];
  const auto coolant = CoolantStateFromCode(ir[pmc::kIrCoolant]);
  w.coolant_known = coolant.has_value();
  machine.coolant = coolant.value_or(CoolantState::kOff);
  machine.compensation_enabled = (w.status & pmc::kStatusCompensationEnabled) != 0;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const std::uint16_t* r = ir + pmc::InputAxisRegister(a, 0);
    hw::AxisState& s = axes[a];
    s.position_mm = CountsToMillimetres(JoinInt32(r + pmc::kIrAxisPositionHi));
    s.servo_direction = static_cast<std::int16_t>(r[pmc::kIrAxisDirection]);
    s.moving = r[pmc::kIrAxisMoving] != 0;
    s.programmed_direction = pmc::ProgrammedDirection(ir[pmc::kIrProgrammedDirection], a);
    s.travel_mm = static_cast<double>(JoinUint32(r + pmc::kIrAxisTravelHi));
    if (a < applied_um.size()) applied_um[a] = CountsToMicrometres(JoinInt32(r + pmc::kIrAxisAppliedHi));
  }
  return w;
}

bool HeartbeatWatch::Fresh(std::uint32_t value, double now_s, double stale_after_s) {
  if (!seen || value != heartbeat) {
    heartbeat = value;
    seen = true;
    changed_at_s = now_s;
    return true;
  }
  return now_s - changed_at_s <= stale_after_s;
}

bool EncodeCommand(std::span<const double> correction_um, std::uint16_t* block) {
  for (std::size_t a = 0; a < correction_um.size(); ++a) {
    std::int32_t c = 0;
    if (!MicrometresToCounts(correction_um[a], &c)) return false;  // NaN or absurd: never sent
    SplitInt32(c, block + pmc::kHrCompensationStride * a);
  }
  return true;
}

void DecodeCommand(const std::uint16_t* block, std::span<double> correction_um) {
  for (std::size_t a = 0; a < correction_um.size(); ++a)
    correction_um[a] = CountsToMicrometres(JoinInt32(block + pmc::kHrCompensationStride * a));
}

bool PmcCommandWithinBound(const std::uint16_t* hr, std::size_t axis_count, double max_abs_um) {
  for (std::size_t a = 0; a < axis_count; ++a)
    if (std::abs(CountsToMicrometres(JoinInt32(hr + pmc::CompensationRegister(a)))) > max_abs_um) return false;
  return true;
}

bool RampCommandToZero(std::uint16_t* block, std::size_t axis_count, double ramp_um_per_s, double elapsed_s) {
  const double step_counts = std::max(1.0, std::round(ramp_um_per_s * std::max(0.0, elapsed_s) / kLengthQuantumUm));
  bool changed = false;
  for (std::size_t a = 0; a < axis_count; ++a) {
    std::uint16_t* r = block + pmc::kHrCompensationStride * a;
    const std::int32_t c = JoinInt32(r);
    if (c == 0) continue;
    const auto step = static_cast<std::int32_t>(std::min<double>(step_counts, std::abs(static_cast<double>(c))));
    SplitInt32(c > 0 ? c - step : c + step, r);
    changed = true;
  }
  return changed;
}

bool CommandWatchdog::Step(std::uint16_t* ir, std::uint16_t* hr, std::size_t axis_count, double since_client_write_s,
                           double elapsed_s) const {
  ir[pmc::kIrStatus] &= static_cast<std::uint16_t>(~pmc::kStatusWatchdogRamping);
  if (timeout_s <= 0 || since_client_write_s <= timeout_s) return false;
  if (!RampCommandToZero(hr + pmc::kHrCompensationBase, axis_count, ramp_um_per_s, elapsed_s)) return false;
  MarkWatchdogRamping(ir);
  return true;
}

void InitRtdModule(std::uint16_t* registers, std::size_t channels, std::uint16_t range_code) {
  std::fill(registers, registers + adam6015::kRegisterCount, std::uint16_t{0});
  for (std::size_t c = 0; c < channels; ++c) registers[adam6015::kTypeCodeAddress + c] = range_code;
  registers[adam6015::kModuleNameAddress] = adam6015::kModuleName;
  registers[adam6015::kModuleNameAddress + 1] = 0;
  registers[adam6015::kChannelEnableAddress] = static_cast<std::uint16_t>((1u << channels) - 1);
}

void EncodeRtdChannel(const hw::RawTemperature& reading, const adam6015::RtdRange& range, std::size_t c,
                      std::uint16_t* registers, std::uint8_t* coils, bool* history_valid) {
  const bool fault = reading.hardware_fault || !std::isfinite(reading.temp_c);
  const std::uint16_t value = fault ? adam6015::kBurnoutRaw : CelsiusToAdamRaw(reading.temp_c, range);
  registers[adam6015::kAiValueAddress + c] = value;
  coils[adam6015::kBurnoutCoilAddress + c] = fault ? 1 : 0;
  if (fault) return;
  std::uint16_t& mx = registers[adam6015::kAiMaxAddress + c];
  std::uint16_t& mn = registers[adam6015::kAiMinAddress + c];
  if (!*history_valid) {
    mx = mn = value;
    *history_valid = true;
  } else {
    mx = std::max(mx, value);
    mn = std::min(mn, value);
  }
}

hw::RawTemperature DecodeRtdChannel(std::uint16_t raw, bool burnout, const adam6015::RtdRange& range) {
  // What the module reports, even when flagged.
  return {AdamRawToCelsius(raw, range), burnout || raw == adam6015::kBurnoutRaw};
}

int CheckRtdCoilWrite(std::size_t channels, int address, int count) {
  const int n = static_cast<int>(channels);
  for (int i = 0; i < count; ++i) {
    const int a = address + i;
    const bool reset_max = a >= adam6015::kResetMaxCoilAddress && a < adam6015::kResetMaxCoilAddress + n;
    const bool reset_min = a >= adam6015::kResetMinCoilAddress && a < adam6015::kResetMinCoilAddress + n;
    if (!reset_max && !reset_min) return kExceptionIllegalDataAddress;
  }
  return 0;
}

void ResetRtdHistory(std::size_t channels, std::uint16_t* registers, std::uint8_t* coils) {
  for (std::size_t c = 0; c < channels; ++c) {
    std::uint8_t& rmax = coils[adam6015::kResetMaxCoilAddress + c];
    std::uint8_t& rmin = coils[adam6015::kResetMinCoilAddress + c];
    if (rmax) registers[adam6015::kAiMaxAddress + c] = registers[adam6015::kAiValueAddress + c];
    if (rmin) registers[adam6015::kAiMinAddress + c] = registers[adam6015::kAiValueAddress + c];
    rmax = rmin = 0;  // the reset coils read back 0
  }
}

}  // namespace trueaxis::drivers
