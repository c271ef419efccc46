// Does the example machine look like a real VMC to a metrologist? Plus the
// ambient profile and homing.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/sim/ambient_profile.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

MachineDescription Vmc850() { return ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml"); }

TEST(Realism, Vmc850ColdTestHasTensOfMicrometresAndAFewOfReversal) {
  VirtualMachine vm(Vmc850(), 1);
  LaserOptions o;
  o.runs = 3;
  LaserInterferometer laser(o, 1);
  laser.Setup(vm, 0, 0);
  const auto m = laser.Measure(vm);
  // Mean deviation per (target, direction), then E (range of means) and the mean reversal.
  std::map<std::pair<double, int>, std::vector<double>> by;
  for (const auto& p : m.points) by[{p.target_mm, DirectionSign(p.direction)}].push_back(p.deviation_um);
  double lo = 1e9, hi = -1e9, rev_sum = 0;
  int n = 0;
  for (double t : m.Targets()) {
    auto mean = [](const std::vector<double>& v) { double s = 0; for (double x : v) s += x; return s / v.size(); };
    const double up = mean(by[{t, 1}]), dn = mean(by[{t, -1}]);
    lo = std::min({lo, up, dn});
    hi = std::max({hi, up, dn});
    rev_sum += dn - up;
    ++n;
  }
  EXPECT_GT(hi - lo, 20.0);   // uncompensated pitch error + shop temperature: tens of µm
  EXPECT_LT(hi - lo, 150.0);
  EXPECT_NEAR(rev_sum / n, 5.0, 1.5);  // configured backlash 5 µm
}

TEST(Realism, AmbientHasDailyAndSeasonalSwing) {
  AmbientDescription d;
  d.mean_c = 20;
  d.seasonal_amplitude_c = 4;
  d.seasonal_peak_day = 200;
  d.daily_amplitude_c = 1.5;
  d.daily_peak_hour = 15;
  d.weather_amplitude_c = 0;
  AmbientProfile a(d, 1);
  const double day = 86400;
  const double summer_afternoon = ParseIsoTime("2026-07-19T15:00:00");
  const double summer_night = ParseIsoTime("2026-07-19T03:00:00");
  const double winter_afternoon = ParseIsoTime("2026-01-15T15:00:00");
  EXPECT_NEAR(a.TemperatureC(summer_afternoon) - a.TemperatureC(summer_night), 3.0, 0.2);
  EXPECT_GT(a.TemperatureC(summer_afternoon) - a.TemperatureC(winter_afternoon), 6.5);
  EXPECT_NEAR(a.TemperatureC(summer_afternoon), 20 + 4 + 1.5, 0.1);
  // Weather: bounded random part, the same for the same seed, different otherwise.
  d.weather_amplitude_c = 0.7;
  AmbientProfile w1(d, 1), w1b(d, 1), w2(d, 2);
  double diff = 0;
  for (int i = 0; i < 30; ++i) {
    EXPECT_DOUBLE_EQ(w1.TemperatureC(i * day), w1b.TemperatureC(i * day));
    diff += std::abs(w1.TemperatureC(i * day) - w2.TemperatureC(i * day));
  }
  EXPECT_GT(diff, 0.5);
  EXPECT_EQ(FormatIsoTime(ParseIsoTime("2026-03-02T07:00:00")), "2026-03-02T07:00:00");
}

TEST(Realism, LongIdleSoaksTheMachineAtTheAirTemperature) {
  VirtualMachine vm(Vmc850(), 1);
  vm.CommandReciprocate(0, 10, 840, 4000);
  vm.Advance(2 * 3600);
  EXPECT_GT(vm.NodeTemperatureC("x_nut") - vm.AmbientC(), 3.0);
  vm.IdleUntil(vm.TimeS() + 10 * 86400.0);
  EXPECT_NEAR(vm.NodeTemperatureC("x_nut"), vm.NodeTemperatureC("bed"), 1.0);
  EXPECT_NEAR(vm.NodeTemperatureC("bed"), vm.AmbientC(), 2.5);
  EXPECT_FALSE(vm.IsMoving(0));
}

TEST(Realism, HomingRepeatsWithinItsSpread) {
  VirtualMachine vm(testing::TestMachine(), 3);  // X: 0.5 µm (1 σ)
  std::vector<double> at_ref;
  for (int i = 0; i < 40; ++i) {
    vm.Home(0);
    vm.MoveTo(0, 100, 2000);
    at_ref.push_back(vm.ErrorUm(0));
  }
  double mean = 0;
  for (double v : at_ref) mean += v;
  mean /= at_ref.size();
  double var = 0;
  for (double v : at_ref) var += (v - mean) * (v - mean);
  const double sd = std::sqrt(var / (at_ref.size() - 1));
  EXPECT_GT(sd, 0.25);  // homing changes where the table is...
  EXPECT_LT(sd, 1.0);   // ...by about its configured repeatability (plus a little heating)
}

}  // namespace
}  // namespace trueaxis::sim
