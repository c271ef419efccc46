// Virtual spindle: heat, growth, marker strain, speed programs.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "trueaxis/sim/spindle.hpp"

namespace trueaxis::sim {
namespace {

TEST(Spindle, AtRestAtStandardTemperatureNothingGrows) {
  VirtualSpindle s({}, SpindleSpeedProgram({{0, 0}}), 20.0);
  s.Advance(3600);
  EXPECT_NEAR(s.GrowthUm(), 0.0, 1e-9);
  EXPECT_NEAR(s.MarkerScale(), 1.0, 1e-12);
  EXPECT_EQ(s.Rpm(), 0.0);
}

TEST(Spindle, UniformSoakGivesAlphaLDeltaT) {
  SpindleDescription d;
  VirtualSpindle s(d, SpindleSpeedProgram({{0, 0}}), 25.0);  // soaked at 25 °C from the start
  EXPECT_NEAR(s.GrowthUm(), d.expansion_per_k * d.length_mm * 5.0 * 1000.0, 1e-9);
  EXPECT_NEAR(s.MarkerStrain(), d.expansion_per_k * 5.0, 1e-15);
  EXPECT_NEAR(s.ZErrorUm(), -s.GrowthUm(), 1e-12);
}

TEST(Spindle, HeatsWhileTurningCoolsWhenStoppedAndRotates) {
  VirtualSpindle s({}, SpindleSpeedProgram::HeatingCoolingDay(10), 20.0);
  double peak = 0, peak_t = 0;
  for (int i = 0; i < 600; ++i) {
    s.Advance(60);
    if (s.GrowthUm() > peak) peak = s.GrowthUm(), peak_t = s.TimeS();
  }
  // A motor spindle grows tens of µm when warm; the peak comes before the stop (6 h).
  EXPECT_GT(peak, 15.0);
  EXPECT_LT(peak, 120.0);
  EXPECT_LE(peak_t, 0.6 * 36000 + 60);
  // Four hours after the stop most of the growth is gone.
  EXPECT_LT(s.GrowthUm(), 0.35 * peak);
  EXPECT_GT(s.FrontBearingC(), 20.0);
  // While warm, the marker (front segment) and the whole spindle disagree: the method's own limit.
  VirtualSpindle w({}, SpindleSpeedProgram({{0, 10000}}), 20.0);
  w.Advance(1800);
  const double from_marker_um = w.MarkerStrain() * w.description().length_mm * 1000.0;
  EXPECT_GT(std::abs(from_marker_um - w.GrowthUm()), 0.01);
  // Angle advances by rpm·t (at steady speed after the ramp).
  const double a0 = w.AngleDeg();
  w.Advance(0.001);  // 10000 rpm = 60°/ms
  EXPECT_NEAR(std::fmod(w.AngleDeg() - a0 + 360.0, 360.0), 60.0, 1e-6);
}

TEST(Spindle, HoldStopsTheSpindleWhateverTheProgram) {
  VirtualSpindle s({}, SpindleSpeedProgram({{0, 8000}}), 20.0);
  s.Advance(60);
  EXPECT_EQ(s.Rpm(), 8000);
  s.Hold(true);
  s.Advance(60);
  EXPECT_EQ(s.Rpm(), 0);
  s.Hold(false);
  s.Advance(60);
  EXPECT_EQ(s.Rpm(), 8000);
}

TEST(Spindle, SpeedProgramParsesAndRefusesNonsense) {
  const auto p = SpindleSpeedProgram::Parse("0:0,600:8000,1200:0");
  EXPECT_EQ(p.RpmAt(599), 0);
  EXPECT_EQ(p.RpmAt(600), 8000);
  EXPECT_EQ(p.RpmAt(5000), 0);
  EXPECT_EQ(SpindleSpeedProgram::Parse(p.ToString()).steps().size(), 3u);
  EXPECT_THROW(SpindleSpeedProgram::Parse("0:0,600"), std::invalid_argument);
  EXPECT_THROW(SpindleSpeedProgram::Parse("600:10,0:0"), std::invalid_argument);
  EXPECT_THROW(SpindleSpeedProgram::Parse("0:-5"), std::invalid_argument);
  SpindleDescription bad;
  bad.front_length_mm = 400;
  EXPECT_THROW(VirtualSpindle(bad, p), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::sim

#include "sim_test_util.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

TEST(Spindle, GrowthReachesTheVirtualMachinesZErrorThroughTheHook) {
  VirtualMachine vm(testing::TestMachine(), 1);
  const std::size_t z = vm.AxisCount() - 1;
  const double before = vm.ErrorAtUm(z, 10.0, +1);
  const double actual_before = vm.ActualMm(z);
  VirtualSpindle s({}, SpindleSpeedProgram({{0, 10000}}), 20.0);
  s.Advance(3600);
  ASSERT_GT(s.GrowthUm(), 5.0);
  vm.SetExtraErrorUm(z, s.ZErrorUm());
  EXPECT_NEAR(vm.ErrorAtUm(z, 10.0, +1) - before, -s.GrowthUm(), 1e-9);
  EXPECT_NEAR((vm.ActualMm(z) - actual_before) * 1000.0, -s.GrowthUm(), 1e-6);
}

}  // namespace
}  // namespace trueaxis::sim
