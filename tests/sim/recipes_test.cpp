// The recipe of docs/machine-file.md, compiled and run (shorter), so the
// documentation cannot drift from the API.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

TEST(Recipes, DocExampleRuns) {
  VirtualMachine vm(ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml"), 7);
  vm.SetCoolant(CoolantState::kFlood);
  vm.CommandReciprocate(0, 50, 800, 3000, /*duty=*/0.6);
  vm.Advance(1800);
  SensorFault spikes{SensorFaultKind::kSpikes};
  spikes.spike_probability = 0.02;
  EXPECT_TRUE(vm.SetSensorFault("x_nut", spikes));
  EXPECT_TRUE(vm.SetSensorFault("ambient", {SensorFaultKind::kOpen}));
  int calls = 0;
  vm.SetController(0.02, [&](VirtualMachine& m) { ++calls; });
  LaserOptions o;
  o.runs = 2;
  o.spacing_mm = 200;
  LaserInterferometer laser(o, 7);
  laser.Setup(vm, 0, vm.description().axes[0].reference_mm);
  auto m = laser.Measure(vm, {{"state", "compensated"}});
  EXPECT_EQ(m.Meta("state").value_or(""), "compensated");
  EXPECT_GT(calls, 1000);
  // The open ambient RTD is flagged by the module: not read (NaN) in the file.
  const auto amb = m.SensorIndex("ambient");
  ASSERT_TRUE(amb.has_value());
  EXPECT_TRUE(std::isnan(m.points.front().temperatures_c[*amb]));
  const auto path = (std::filesystem::temp_directory_path() / "trueaxis_recipe_x.csv").string();
  measure::WriteMeasurementCsv(m, path);
  const auto back = measure::ReadMeasurementCsv(path);
  EXPECT_EQ(back.points.size(), m.points.size());
  std::filesystem::remove(path);
  const double before = vm.TimeS();
  vm.IdleUntil(vm.TimeS() + 3 * 86400 + 3600);
  vm.Home(0);
  EXPECT_GT(vm.TimeS() - before, 3 * 86400.0);
  EXPECT_EQ(vm.coolant(), CoolantState::kOff);
}

}  // namespace
}  // namespace trueaxis::sim
