// Physics a metrologist would check on the virtual machine.
#include <cmath>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

using testing::TestMachine;

TEST(Physics, UniformTemperatureGivesAlphaLDeltaT) {
  VirtualMachine vm(TestMachine(), 1);
  const double x = 500;
  vm.Soak(20.0);
  const double e20 = vm.ErrorAtUm(0, x, +1) - vm.ErrorAtUm(0, 0, +1);
  vm.Soak(25.0);
  const double e25 = vm.ErrorAtUm(0, x, +1) - vm.ErrorAtUm(0, 0, +1);
  // α·L·ΔT = 11.5 µm/m/°C · 0.5 m · 5 °C
  EXPECT_NEAR(e25 - e20, 11.5 * 0.5 * 5, 1e-6);
  // Y is fixed at the max end: the screw grows towards −, and the error
  // relative to the fixed end has the opposite sign and scales with the
  // distance from the fixed end.
  const double y20 = vm.ErrorAtUm(1, 100, +1);
  vm.Soak(20.0);
  const double y20b = vm.ErrorAtUm(1, 100, +1);
  EXPECT_NEAR(y20 - y20b, -11.5 * 0.3 * 5 - 11.5 * 0.06 * 5, 1e-6);  // 300 mm of travel + half the 120 mm overhang
}

TEST(Physics, LaserSeesUniformGrowthAndMaterialCompensationRemovesIt) {
  LaserOptions o;
  o.noise_nm = 0;
  o.air_sensor_error_c = 0;
  o.material_sensor_error_c = 0;
  auto read_at = [&](bool material, double temp) {
    // A machine soaked in a constant ambient of `temp`: uniform and steady.
    VirtualMachine vm(TestMachine("mean_c = " + std::to_string(temp) +
                                  "\nseasonal_amplitude_c = 0\ndaily_amplitude_c = 0\nweather_amplitude_c = 0\n"),
                      1);
    LaserOptions lo = o;
    lo.material_compensation = material;
    LaserInterferometer laser(lo, 3);
    laser.Setup(vm, 0, 0);
    vm.MoveTo(0, 400, 2000);
    return laser.ReadMm(vm);
  };
  const double off = read_at(false, 26) - read_at(false, 20);
  EXPECT_NEAR(off * 1000, 11.5 * 0.4 * 6, 0.01);
  const double on = read_at(true, 26) - read_at(true, 20);
  EXPECT_NEAR(on * 1000, 0, 0.05);  // same CTE for screw and material: only the product term remains
}

TEST(Physics, ReversalEqualsConfiguredBacklash) {
  VirtualMachine vm(TestMachine(), 2);
  // Backlash 6 µm on X; the flank part (1 µm rms default) makes the reversal
  // vary along the axis, so average it out over the travel.
  double sum = 0;
  int n = 0;
  for (double x = 50; x <= 550; x += 25) {
    vm.MoveTo(0, x - 5, 2000);
    vm.MoveTo(0, x, 2000);
    const double fwd = vm.ErrorUm(0);
    vm.MoveTo(0, x + 5, 2000);
    vm.MoveTo(0, x, 2000);
    const double rev = vm.ErrorUm(0);
    sum += rev - fwd;
    ++n;
  }
  EXPECT_NEAR(sum / n, 6.0, 0.8);
}

TEST(Physics, WarmUpFansAboutTheFixedEnd) {
  VirtualMachine vm(TestMachine(), 3);
  auto err = [&](double x) { return vm.ErrorAtUm(0, x, +1); };
  std::vector<double> cold;
  for (double x = 0; x <= 600; x += 100) cold.push_back(err(x));
  const double cold0 = cold.front(), cold600 = cold.back();
  vm.CommandReciprocate(0, 0, 600, 4000);
  vm.Advance(2 * 3600);
  vm.CommandStop(0);
  const double d0 = err(0) - cold0, d600 = err(600) - cold600;
  // Near the fixed end (x = 0) the error barely moves; at the far end the
  // screw has grown tens of µm: the curve swings up about the fixed end.
  EXPECT_GT(d600, 15.0);
  EXPECT_LT(std::abs(d0), 0.15 * d600);
  // Monotone fan: the change grows with distance from the fixed end.
  // (Measured against the cold curve sampled on the same grid.)
  for (int i = 1; i < static_cast<int>(cold.size()); ++i)
    EXPECT_GT(err(100.0 * i) - cold[i], err(100.0 * (i - 1)) - cold[i - 1]) << "at " << 100 * i << " mm";
  EXPECT_GT(vm.NodeTemperatureC("x_nut") - vm.NodeTemperatureC("ambient"), 3.0);
}

TEST(Physics, HeatFollowsTheNut) {
  VirtualMachine vm(TestMachine(), 4);
  // Reciprocate only over the first 150 mm: that part of the screw warms,
  // the far part stays near ambient.
  vm.CommandReciprocate(0, 0, 150, 3000);
  vm.Advance(3600);
  const double near = vm.NodeTemperatureC("x_screw_03");
  const double far = vm.NodeTemperatureC("x_screw_20");
  EXPECT_GT(near - far, 1.0);
}

TEST(Physics, CoolantLowersNutTemperatureRise) {
  auto rise = [](CoolantState c) {
    VirtualMachine vm(TestMachine(), 5);
    vm.SetCoolant(c);
    const double t0 = vm.NodeTemperatureC("x_nut");
    vm.CommandReciprocate(0, 0, 600, 3000);
    vm.Advance(3 * 3600);
    return vm.NodeTemperatureC("x_nut") - t0;
  };
  const double off = rise(CoolantState::kOff), flood = rise(CoolantState::kFlood), mist = rise(CoolantState::kMist);
  EXPECT_GT(off, 3.0);
  EXPECT_LT(flood, 0.7 * off);
  EXPECT_LT(mist, off);
}

TEST(Physics, CompensationThroughCncLinkMovesTheTable) {
  VirtualMachine vm(TestMachine(), 6);
  vm.MoveTo(0, 300, 2000);  // approached forward
  const double before = vm.ActualMm(0);
  hw::CncLink& cnc = vm;
  const double corr[2] = {12.5, 0};
  ASSERT_TRUE(cnc.WriteCompensation(corr));
  // Same direction as the last motion: no backlash to take up, the table
  // moves by the correction (plus the pitch error change over 12.5 µm: nil).
  EXPECT_NEAR((vm.ActualMm(0) - before) * 1000, 12.5, 0.01);
  hw::AxisState st[2];
  hw::CncState ms;
  ASSERT_TRUE(cnc.Read(st, ms));
  EXPECT_DOUBLE_EQ(st[0].position_mm, 300);  // the CNC still reports the commanded position
  EXPECT_EQ(st[0].servo_direction, 1);
  EXPECT_FALSE(st[0].moving);
  EXPECT_EQ(ms.coolant, CoolantState::kOff);
  EXPECT_TRUE(ms.compensation_enabled);
  // A correction against the last motion first takes up the 6 µm of play.
  const double back[2] = {0, 0};
  ASSERT_TRUE(cnc.WriteCompensation(back));
  ASSERT_TRUE(cnc.Read(st, ms));
  EXPECT_EQ(st[0].servo_direction, 1);  // programmed direction, not the compensation's
  // Now resting on the other flank: the shift is the reversal at 300 mm.
  const double reversal = vm.ErrorAtUm(0, 300, -1) - vm.ErrorAtUm(0, 300, +1);
  EXPECT_NEAR(reversal, 6.0, 2.0);
  EXPECT_NEAR((vm.ActualMm(0) - before) * 1000, reversal, 0.01);
  // Disabled on the CNC side: accepted, no effect. Link fault: refused.
  vm.SetCompensationEnabled(false);
  const double big[2] = {50, 0};
  EXPECT_TRUE(cnc.WriteCompensation(big));
  EXPECT_NEAR((vm.ActualMm(0) - before) * 1000, reversal, 0.01);
  vm.SetLinkFault(true);
  EXPECT_FALSE(cnc.WriteCompensation(back));
  EXPECT_FALSE(cnc.Read(st, ms));
  vm.SetLinkFault(false);
  vm.SetCompensationEnabled(true);
  const double nan[2] = {std::nan(""), 0};
  EXPECT_FALSE(cnc.WriteCompensation(nan));
}

TEST(Physics, NonBlockingMotionReportsDirectionAndMoving) {
  VirtualMachine vm(TestMachine(), 8);
  hw::AxisState st[2];
  hw::CncState ms;
  vm.CommandMove(0, 100, 6000);  // 100 mm/s: 1 s
  vm.Advance(0.5);
  ASSERT_TRUE(vm.Read(st, ms));
  EXPECT_TRUE(st[0].moving);
  EXPECT_EQ(st[0].servo_direction, 1);
  EXPECT_NEAR(st[0].position_mm, 50, 1e-9);
  vm.Advance(0.5);
  ASSERT_TRUE(vm.Read(st, ms));
  EXPECT_FALSE(st[0].moving);
  EXPECT_NEAR(st[0].position_mm, 100, 1e-9);
  for (double x : {123.456789, 17.0, 599.999}) {  // blocking moves end at rest, exactly on target
    vm.MoveTo(0, x, 1234.5);
    ASSERT_TRUE(vm.Read(st, ms));
    EXPECT_FALSE(st[0].moving);
    EXPECT_FALSE(vm.IsMoving(0));
    EXPECT_DOUBLE_EQ(st[0].position_mm, x);
  }
  vm.CommandMove(0, 20, 6000);
  vm.Advance(0.2);
  ASSERT_TRUE(vm.Read(st, ms));
  EXPECT_EQ(st[0].servo_direction, -1);
  vm.SetCoolant(CoolantState::kMist);
  ASSERT_TRUE(vm.Read(st, ms));
  EXPECT_EQ(ms.coolant, CoolantState::kMist);
  EXPECT_THROW(vm.CommandMove(0, 700, 1000), std::invalid_argument);  // beyond the travel
  // The travelled path counts both directions (the CNC's distance counter).
  vm.MoveTo(0, 20, 6000);
  const double travel0 = vm.TravelMm(0);
  vm.MoveTo(0, 320, 6000);
  vm.MoveTo(0, 120, 6000);
  EXPECT_NEAR(vm.TravelMm(0) - travel0, 300 + 200, 1e-6);
  vm.Advance(10);  // standing still adds nothing
  EXPECT_NEAR(vm.TravelMm(0) - travel0, 500, 1e-6);
  // Machining duty cycle: moving half of the time.
  vm.CommandReciprocate(0, 100, 400, 3000, 0.5);
  int moving = 0;
  for (int i = 0; i < 600; ++i) {
    vm.Advance(1);
    ASSERT_TRUE(vm.Read(st, ms));
    moving += st[0].moving;
  }
  EXPECT_NEAR(moving / 600.0, 0.5, 0.1);
}

TEST(Physics, LaserSeesACompensationAppliedInTheLoop) {
  // An oracle compensator (it knows the true error) writes through CncLink
  // every second while the laser test runs: the laser must see a flat axis,
  // where without it the same test shows tens of µm.
  auto range_of_means = [](const measure::Measurement& m) {
    std::map<std::pair<double, int>, std::pair<double, int>> acc;
    for (const auto& p : m.points) {
      auto& a = acc[{p.target_mm, DirectionSign(p.direction)}];
      a.first += p.deviation_um;
      a.second += 1;
    }
    double lo = 1e9, hi = -1e9;
    for (const auto& [k, a] : acc) {
      lo = std::min(lo, a.first / a.second);
      hi = std::max(hi, a.first / a.second);
    }
    return hi - lo;
  };
  auto run = [&](bool compensate) {
    VirtualMachine vm(TestMachine(), 12);
    vm.CommandReciprocate(0, 0, 600, 4000);  // warm first: geometric + thermal error
    vm.Advance(3600);
    vm.CommandStop(0);
    if (compensate)
      vm.SetController(0.02, [](VirtualMachine& m) {  // 50 Hz, like a PMC-window compensator
        hw::AxisState st[2];
        hw::CncState cs;
        if (!m.Read(st, cs)) return;
        double corr[2];
        for (int i = 0; i < 2; ++i)
          corr[i] = -m.ErrorAtUm(i, st[i].position_mm, st[i].servo_direction == 0 ? 1 : st[i].servo_direction);
        m.WriteCompensation(corr);
      });
    LaserOptions o;
    o.runs = 2;
    o.spacing_mm = 50;
    LaserInterferometer laser(o, 1);
    laser.Setup(vm, 0, 0);
    return range_of_means(laser.Measure(vm));
  };
  const double plain = run(false), compensated = run(true);
  EXPECT_GT(plain, 20.0);
  EXPECT_LT(compensated, 1.5);
}

TEST(Physics, CoarseThermalStepStaysStableAndClose) {
  // The network sub-steps below its stability limit, so even a 30 s step
  // (twice the limit of the screw segments) neither blows up nor drifts far.
  auto nut_after = [](const std::string& step) {
    auto toml = testing::TestMachineToml();
    toml.replace(toml.find("start = "), 0, "thermal_step_s = " + step + "\n");
    VirtualMachine vm(ParseMachineToml(toml, "t.toml"), 1);
    vm.CommandReciprocate(0, 0, 600, 3000);
    vm.Advance(2 * 3600);
    return std::make_pair(vm.NodeTemperatureC("x_nut"), vm.ThermalGrowthUm(0, 600));
  };
  const auto fine = nut_after("1.0"), coarse = nut_after("30");
  EXPECT_NEAR(coarse.first, fine.first, 0.2);
  EXPECT_NEAR(coarse.second, fine.second, 1.0);
  EXPECT_TRUE(std::isfinite(coarse.first));
}

TEST(Physics, AdvanceSlicingDoesNotChangeResults) {
  VirtualMachine a(TestMachine(), 9), b(TestMachine(), 9);
  a.CommandReciprocate(0, 0, 600, 3000);
  b.CommandReciprocate(0, 0, 600, 3000);
  a.Advance(600);
  for (int i = 0; i < 600 * 7; ++i) b.Advance(1.0 / 7);
  EXPECT_NEAR(a.NodeTemperatureC("x_nut"), b.NodeTemperatureC("x_nut"), 1e-9);
  EXPECT_NEAR(a.CommandedMm(0), b.CommandedMm(0), 1e-6);
}

}  // namespace
}  // namespace trueaxis::sim
