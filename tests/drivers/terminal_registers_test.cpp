// The terminal register model on its own: what a terminal encodes a client decodes to the same
// values (every field, the limits, the fault flags, negative values), the command block, the
// writes a terminal accepts, and the watchdog ramp.
#include "trueaxis/drivers/terminal_registers.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace trueaxis::drivers {
namespace {

constexpr std::size_t kAxes = pmc::kMaxAxes;

struct Image {
  std::array<std::uint16_t, pmc::kInputRegisterCount> ir{};
  std::array<std::uint16_t, pmc::kHoldingImageCount> hr{};  // enable, command block, the window's copy
};

std::vector<hw::AxisState> SampleAxes() {
  std::vector<hw::AxisState> axes(kAxes);
  const double positions[kAxes] = {0.0, -1.0001, 850.1234, -214748.3648, 214748.3647, 0.00005, -0.00004, 12.3};
  const double travel[kAxes] = {0, 1, 123456.9, 4294967295.0, 65536, 7, 1e12, 0.4};
  for (std::size_t a = 0; a < kAxes; ++a) {
    axes[a].position_mm = positions[a];
    axes[a].servo_direction = static_cast<int>(a % 3) - 1;
    axes[a].moving = a % 2 == 1;
    axes[a].programmed_direction = 1 - static_cast<int>((a + 1) % 3);
    axes[a].travel_mm = travel[a];
  }
  return axes;
}

TEST(TerminalRegisters, PmcStateRoundTripsEveryField) {
  for (int coolant = 0; coolant < kCoolantStateCount; ++coolant) {
    for (int enable = 0; enable <= 1; ++enable) {
      Image img;
      InitPmcImage(img.ir.data(), img.hr.data(), kAxes, enable == 1);
      const auto axes = SampleAxes();
      std::vector<double> travel(kAxes);
      for (std::size_t a = 0; a < kAxes; ++a) travel[a] = axes[a].travel_mm;
      PmcExchange e;
      e.heartbeat = 0xABCD1234u + static_cast<std::uint32_t>(coolant);
      e.machine_read_ok = true;
      e.temperatures_read_ok = coolant % 2 == 0;
      e.machine = {static_cast<CoolantState>(coolant), true};
      e.axes = axes;
      e.travel_mm = travel;
      e.read_age_ms = 12.7;
      EncodePmcState(e, img.ir.data(), img.hr.data());

      std::vector<hw::AxisState> got(kAxes);
      hw::CncState machine;
      std::vector<double> applied(kAxes, -1.0);
      ASSERT_TRUE(PmcLayoutMatches(img.ir.data(), kAxes));
      EXPECT_FALSE(PmcLayoutMatches(img.ir.data(), kAxes - 1));
      const PmcWindow w = DecodePmcWindow(img.ir.data(), got, machine, applied);
      EXPECT_EQ(w.layout_version, pmc::kLayoutVersion);
      EXPECT_EQ(w.axis_count, kAxes);
      EXPECT_EQ(w.heartbeat, e.heartbeat);
      EXPECT_TRUE(w.machine_read_ok());
      EXPECT_EQ((w.status & pmc::kStatusTemperatureReadOk) != 0, e.temperatures_read_ok);
      EXPECT_FALSE(w.watchdog_ramping());
      EXPECT_EQ(w.read_age_ms, 12);
      EXPECT_TRUE(w.coolant_known);
      EXPECT_EQ(machine.coolant, static_cast<CoolantState>(coolant));
      // the effective enable: the CNC's AND the PMC enable register
      EXPECT_EQ(machine.compensation_enabled, enable == 1);
      for (std::size_t a = 0; a < kAxes; ++a) {
        SCOPED_TRACE(a);
        EXPECT_NEAR(got[a].position_mm, axes[a].position_mm, 0.00005 + 1e-12);
        EXPECT_EQ(got[a].servo_direction, axes[a].servo_direction);
        EXPECT_EQ(got[a].moving, axes[a].moving);
        EXPECT_EQ(got[a].programmed_direction, axes[a].programmed_direction);
        EXPECT_EQ(got[a].travel_mm, std::clamp(std::floor(axes[a].travel_mm), 0.0, 4294967295.0));
        EXPECT_EQ(applied[a], 0.0);  // nothing applied yet
      }
      // the holding registers' copy (what an FC 23 reads) is the window, register for register
      CopyWindowToHolding(img.ir.data(), img.hr.data(), kAxes);
      for (int i = 0; i < pmc::InputWindowLength(kAxes); ++i)
        EXPECT_EQ(img.hr[static_cast<std::size_t>(pmc::kHrWindowCopyBase + i)], img.ir[static_cast<std::size_t>(i)]) << i;
      EXPECT_EQ(PmcHoldingImageLength(kAxes), pmc::kHoldingImageCount);
      // the int32 limits hold exactly; beyond them the value saturates
      EXPECT_DOUBLE_EQ(got[3].position_mm, -214748.3648);
      EXPECT_DOUBLE_EQ(got[4].position_mm, 214748.3647);
      EXPECT_DOUBLE_EQ(got[1].position_mm, -1.0001);
    }
  }
}

TEST(TerminalRegisters, AStaleReadKeepsTheLastStateAndClearsItsBit) {
  Image img;
  InitPmcImage(img.ir.data(), img.hr.data(), 2, true);
  std::vector<hw::AxisState> axes(2);
  axes[0].position_mm = -42.5;
  axes[1].position_mm = 7.25;
  const std::vector<double> travel = {3, 4};
  PmcExchange e{1, true, true, {CoolantState::kMist, true}, axes, travel, 0};
  EncodePmcState(e, img.ir.data(), img.hr.data());
  PmcExchange stale{2, false, false, {CoolantState::kOff, false}, {}, {}, 1e9};
  EncodePmcState(stale, img.ir.data(), img.hr.data());
  std::vector<hw::AxisState> got(2);
  hw::CncState machine;
  const PmcWindow w = DecodePmcWindow(img.ir.data(), got, machine, {});
  EXPECT_FALSE(w.machine_read_ok());
  EXPECT_EQ(w.heartbeat, 2u);
  EXPECT_EQ(w.read_age_ms, 65535);  // saturated
  EXPECT_EQ(machine.coolant, CoolantState::kMist);
  EXPECT_DOUBLE_EQ(got[0].position_mm, -42.5);
  EXPECT_DOUBLE_EQ(got[1].travel_mm, 4.0);
}

TEST(TerminalRegisters, AnUnknownCoolantCodeIsNotReadAsOff) {
  Image img;
  InitPmcImage(img.ir.data(), img.hr.data(), 1, true);
  img.ir[pmc::kIrCoolant] = 9;
  std::vector<hw::AxisState> got(1);
  hw::CncState machine;
  EXPECT_FALSE(DecodePmcWindow(img.ir.data(), got, machine, {}).coolant_known);
}

TEST(TerminalRegisters, CommandBlockRoundTripsAndRefusesWhatCannotBeSent) {
  const std::vector<double> command = {0.0, -0.1, 999.9, -1000.0, 12.34, -12.36, 0.04, -214748364.8};
  std::array<std::uint16_t, CommandBlockLength(kAxes)> block{};
  ASSERT_TRUE(EncodeCommand(command, block.data()));
  std::vector<double> back(kAxes);
  DecodeCommand(block.data(), back);
  for (std::size_t a = 0; a < kAxes; ++a) EXPECT_NEAR(back[a], command[a], 0.05 + 1e-9) << a;
  EXPECT_DOUBLE_EQ(back[1], -0.1);
  EXPECT_DOUBLE_EQ(back[6], 0.0);  // below half a count
  EXPECT_EQ(block[2], 0xFFFF);      // -1 count, high word first
  EXPECT_EQ(block[3], 0xFFFF);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(EncodeCommand(std::vector<double>{1.0, nan}, block.data()));
  EXPECT_FALSE(EncodeCommand(std::vector<double>{3e8}, block.data()));  // beyond ±214.7 m
}

TEST(TerminalRegisters, ATerminalAcceptsOnlyEnableAndTheCommandBlockWithinItsBound) {
  Image img;
  InitPmcImage(img.ir.data(), img.hr.data(), 3, true);
  std::array<std::uint16_t, pmc::kHoldingRegisterCount> candidate{};
  std::vector<std::uint16_t> words(6);
  ASSERT_TRUE(EncodeCommand(std::vector<double>{-999.9, 0.5, 1000.0}, words.data()));
  auto at = [&](int i) { return words[static_cast<std::size_t>(i)]; };
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, pmc::kHrCompensationBase, 6, at, 1000.0, candidate.data()), 0);
  std::vector<double> back(3);
  DecodeCommand(candidate.data() + pmc::kHrCompensationBase, back);
  EXPECT_DOUBLE_EQ(back[0], -999.9);
  EXPECT_DOUBLE_EQ(back[2], 1000.0);
  // beyond the bound, on either side
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, pmc::kHrCompensationBase, 6, at, 999.0, candidate.data()),
            kExceptionIllegalDataValue);
  // a fourth axis the terminal does not have, a reserved register
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, pmc::kHrCompensationBase + 2, 6, at, 1000.0, candidate.data()),
            kExceptionIllegalDataAddress);
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, 1, 1, at, 1000.0, candidate.data()), kExceptionIllegalDataAddress);
  // the enable register takes 0/1 only
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, pmc::kHrEnable, 1, [](int) { return std::uint16_t{0}; }, 1000.0,
                          candidate.data()),
            0);
  EXPECT_EQ(candidate[pmc::kHrEnable], 0);
  EXPECT_EQ(CheckPmcWrite(img.hr.data(), 3, pmc::kHrEnable, 1, [](int) { return std::uint16_t{2}; }, 1000.0,
                          candidate.data()),
            kExceptionIllegalDataValue);
}

TEST(TerminalRegisters, WriteResultPublishesWhatTheCncApplies) {
  Image img;
  InitPmcImage(img.ir.data(), img.hr.data(), 2, true);
  const std::vector<double> applied = {-3.4, 250.0};
  EncodeWriteResult(true, applied, img.ir.data());
  EncodeWriteResult(false, std::vector<double>{99.0, 99.0}, img.ir.data());  // refused: applied stays
  std::vector<hw::AxisState> got(2);
  hw::CncState machine;
  std::vector<double> back(2);
  const PmcWindow w = DecodePmcWindow(img.ir.data(), got, machine, back);
  EXPECT_EQ(w.write_count, 1);
  EXPECT_EQ(w.status & pmc::kStatusLastWriteOk, 0);
  EXPECT_DOUBLE_EQ(back[0], -3.4);
  EXPECT_DOUBLE_EQ(back[1], 250.0);
}

TEST(TerminalRegisters, WatchdogRampsTheCommandToZeroWithoutOvershoot) {
  Image img;
  InitPmcImage(img.ir.data(), img.hr.data(), 3, true);
  ASSERT_TRUE(EncodeCommand(std::vector<double>{25.0, -25.0, 0.0}, img.hr.data() + pmc::kHrCompensationBase));
  const CommandWatchdog watchdog{2.0, 10.0};  // after 2 s without a write, 10 µm/s
  std::vector<double> c(3);
  // a client wrote 1 s ago: hold
  EXPECT_FALSE(watchdog.Step(img.ir.data(), img.hr.data(), 3, 1.0, 0.5));
  DecodeCommand(img.hr.data() + pmc::kHrCompensationBase, c);
  EXPECT_DOUBLE_EQ(c[0], 25.0);
  // silent for 3 s: one step of 0.5 s at 10 µm/s = 5 µm towards 0 on both signs
  EXPECT_TRUE(watchdog.Step(img.ir.data(), img.hr.data(), 3, 3.0, 0.5));
  EXPECT_NE(img.ir[pmc::kIrStatus] & pmc::kStatusWatchdogRamping, 0);
  DecodeCommand(img.hr.data() + pmc::kHrCompensationBase, c);
  EXPECT_DOUBLE_EQ(c[0], 20.0);
  EXPECT_DOUBLE_EQ(c[1], -20.0);
  EXPECT_DOUBLE_EQ(c[2], 0.0);
  // a long gap does not cross zero
  EXPECT_TRUE(watchdog.Step(img.ir.data(), img.hr.data(), 3, 60.0, 10.0));
  DecodeCommand(img.hr.data() + pmc::kHrCompensationBase, c);
  EXPECT_DOUBLE_EQ(c[0], 0.0);
  EXPECT_DOUBLE_EQ(c[1], 0.0);
  // nothing left to ramp: the bit clears
  EXPECT_FALSE(watchdog.Step(img.ir.data(), img.hr.data(), 3, 61.0, 0.1));
  EXPECT_EQ(img.ir[pmc::kIrStatus] & pmc::kStatusWatchdogRamping, 0);
  // a tiny step still moves one count (never stuck)
  ASSERT_TRUE(EncodeCommand(std::vector<double>{0.3, 0, 0}, img.hr.data() + pmc::kHrCompensationBase));
  EXPECT_TRUE(watchdog.Step(img.ir.data(), img.hr.data(), 3, 60.0, 1e-6));
  DecodeCommand(img.hr.data() + pmc::kHrCompensationBase, c);
  EXPECT_NEAR(c[0], 0.2, 1e-12);
  // watchdog off (0): hold for ever
  const CommandWatchdog off{0.0, 10.0};
  EXPECT_FALSE(off.Step(img.ir.data(), img.hr.data(), 3, 1e6, 1.0));
}

TEST(TerminalRegisters, RtdChannelRoundTripsWithinOneCountAndFlagsFaults) {
  std::array<std::uint16_t, adam6015::kRegisterCount> regs{};
  std::array<std::uint8_t, adam6015::kCoilCount> coils{};
  InitRtdModule(regs.data(), 5, 0x24);
  EXPECT_EQ(regs[adam6015::kModuleNameAddress], adam6015::kModuleName);
  EXPECT_EQ(regs[adam6015::kChannelEnableAddress], 0x1F);
  EXPECT_EQ(regs[adam6015::kTypeCodeAddress + 4], 0x24);
  EXPECT_EQ(regs[adam6015::kTypeCodeAddress + 5], 0);
  const adam6015::RtdRange& range = *FindRtdRange(0x24);  // -200..200 °C
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const hw::RawTemperature in[5] = {{-12.345, false}, {21.5, false}, {20.0, true}, {nan, false}, {250.0, false}};
  bool valid[5] = {};
  for (std::size_t c = 0; c < 5; ++c) EncodeRtdChannel(in[c], range, c, regs.data(), coils.data(), &valid[c]);
  auto decode = [&](std::size_t c) {
    return DecodeRtdChannel(regs[adam6015::kAiValueAddress + c], coils[adam6015::kBurnoutCoilAddress + c] != 0, range);
  };
  EXPECT_NEAR(decode(0).temp_c, -12.345, AdamResolutionC(range));
  EXPECT_FALSE(decode(0).hardware_fault);
  EXPECT_NEAR(decode(1).temp_c, 21.5, AdamResolutionC(range));
  EXPECT_TRUE(decode(2).hardware_fault);  // the source's own flag: burn-out
  EXPECT_TRUE(decode(3).hardware_fault);  // not a number: burn-out
  EXPECT_TRUE(decode(4).hardware_fault);  // over range reads as burn-out, without the coil
  EXPECT_EQ(coils[adam6015::kBurnoutCoilAddress + 4], 0);
  EXPECT_TRUE(DecodeRtdChannel(adam6015::kBurnoutRaw, false, range).hardware_fault);
  EXPECT_FALSE(valid[2]);  // a fault starts no history

  // history: max/min follow the readings; a reset coil restarts them at the present value
  EncodeRtdChannel({30.0, false}, range, 1, regs.data(), coils.data(), &valid[1]);
  EncodeRtdChannel({25.0, false}, range, 1, regs.data(), coils.data(), &valid[1]);
  EXPECT_NEAR(AdamRawToCelsius(regs[adam6015::kAiMaxAddress + 1], range), 30.0, AdamResolutionC(range));
  EXPECT_NEAR(AdamRawToCelsius(regs[adam6015::kAiMinAddress + 1], range), 21.5, AdamResolutionC(range));
  EXPECT_EQ(CheckRtdCoilWrite(5, adam6015::kResetMaxCoilAddress + 1, 1), 0);
  EXPECT_EQ(CheckRtdCoilWrite(5, adam6015::kResetMaxCoilAddress + 5, 1), kExceptionIllegalDataAddress);
  EXPECT_EQ(CheckRtdCoilWrite(5, adam6015::kBurnoutCoilAddress, 1), kExceptionIllegalDataAddress);
  coils[adam6015::kResetMaxCoilAddress + 1] = 1;
  ResetRtdHistory(5, regs.data(), coils.data());
  EXPECT_NEAR(AdamRawToCelsius(regs[adam6015::kAiMaxAddress + 1], range), 25.0, AdamResolutionC(range));
  EXPECT_EQ(coils[adam6015::kResetMaxCoilAddress + 1], 0);

  // type codes: only the module's channels, only known codes
  auto code = [](std::uint16_t v) { return [v](int) { return v; }; };
  EXPECT_EQ(CheckRtdTypeCodeWrite(5, adam6015::kTypeCodeAddress + 4, 1, code(0x03A4)), 0);
  EXPECT_EQ(CheckRtdTypeCodeWrite(5, adam6015::kTypeCodeAddress + 5, 1, code(0x20)), kExceptionIllegalDataAddress);
  EXPECT_EQ(CheckRtdTypeCodeWrite(5, adam6015::kTypeCodeAddress, 1, code(0x99)), kExceptionIllegalDataValue);
}

TEST(TerminalRegisters, ModuleLayoutAndHeartbeatWatch) {
  EXPECT_EQ(RtdModulesFor(0), 0u);
  EXPECT_EQ(RtdModulesFor(7), 1u);
  EXPECT_EQ(RtdModulesFor(8), 2u);
  EXPECT_EQ(RtdModuleChannels(9, 0), 7u);
  EXPECT_EQ(RtdModuleChannels(9, 1), 2u);
  EXPECT_EQ(RtdModuleChannels(9, 2), 0u);
  HeartbeatWatch hb;
  EXPECT_TRUE(hb.Fresh(5, 100.0, 0.5));
  EXPECT_TRUE(hb.Fresh(5, 100.4, 0.5));
  EXPECT_FALSE(hb.Fresh(5, 100.6, 0.5));  // frozen
  EXPECT_TRUE(hb.Fresh(6, 100.7, 0.5));   // moved again
}

}  // namespace
}  // namespace trueaxis::drivers
