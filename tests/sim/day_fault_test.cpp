// A sensor that dies while the machine runs: the machine file's [[day_fault]] (read by the demo's
// working day) and VirtualMachine::ScheduleSensorFault, which applies it on the thermal grid.
#include <cmath>

#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

const std::string kAxis = "[[axis]]\nname = \"X\"\ntravel_mm = 500\nlead_mm = 10\n";  // lines 1–4

TEST(DayFault, IsReadWithItsSensorHourAndKind) {
  const auto m = ParseMachineToml(kAxis + "[[day_fault]]\nsensor = \"x_nut\"\nat_h = 2.5\nkind = \"stuck\"\n"
                                          "[[day_fault]]\nsensor = \"ambient\"\nat_h = 0\n",
                                  "ok.toml");
  ASSERT_EQ(m.day_faults.size(), 2u);
  EXPECT_EQ(m.day_faults[0].sensor, "x_nut");  // a default sensor (no [[sensor]] tables)
  EXPECT_DOUBLE_EQ(m.day_faults[0].at_h, 2.5);
  EXPECT_EQ(m.day_faults[0].kind, "stuck");
  EXPECT_EQ(m.day_faults[1].kind, "open");  // the default
  EXPECT_TRUE(ParseMachineToml(kAxis, "none.toml").day_faults.empty());
}

TEST(DayFault, BadEntriesNameLineAndField) {
  using testing::ExpectBad;
  ExpectBad({"unknown sensor", kAxis + "[[day_fault]]\nsensor = \"x_screw\"\nat_h = 1\n", 6, "day_fault[0].sensor", "x_nut"});
  ExpectBad({"bad kind", kAxis + "[[day_fault]]\nsensor = \"x_nut\"\nat_h = 1\nkind = \"melted\"\n", 8,
             "day_fault[0].kind", "not a sensor fault"});
  ExpectBad({"none is no fault", kAxis + "[[day_fault]]\nsensor = \"x_nut\"\nat_h = 1\nkind = \"none\"\n", 8,
             "day_fault[0].kind", "not a sensor fault"});
  ExpectBad({"hour out of range", kAxis + "[[day_fault]]\nsensor = \"x_nut\"\nat_h = 30\n", 7, "day_fault[0].at_h"});
  ExpectBad({"hour missing", kAxis + "[[day_fault]]\nsensor = \"x_nut\"\n", 5, "day_fault[0].at_h"});
  ExpectBad({"typo", kAxis + "[[day_fault]]\nsensor = \"x_nut\"\nat_h = 1\nat_hour = 2\n", 8, "day_fault[0].at_hour"});
  ExpectBad({"not a table array", "day_fault = 3\n" + kAxis, 1, "day_fault"});
}

TEST(DayFault, AScheduledFaultStrikesAtItsTimeNotBefore) {
  VirtualMachine vm(testing::TestMachine(), 3);
  const int nut = vm.SensorIndex("x_nut");  // a Pt100 chain: open wire reads the 50 °C rail, unflagged
  ASSERT_GE(nut, 0);
  const double t0 = vm.TimeS();
  ASSERT_TRUE(vm.ScheduleSensorFault("x_nut", SensorFault{SensorFaultKind::kOpen}, t0 + 100));
  EXPECT_FALSE(vm.ScheduleSensorFault("x_spindle", SensorFault{SensorFaultKind::kOpen}, t0 + 100));
  vm.Advance(90);
  EXPECT_LT(vm.sensor(static_cast<std::size_t>(nut)).Latest().temp_c, 30.0);
  EXPECT_EQ(vm.sensor(static_cast<std::size_t>(nut)).fault().kind, SensorFaultKind::kNone);
  vm.Advance(20);
  EXPECT_EQ(vm.sensor(static_cast<std::size_t>(nut)).fault().kind, SensorFaultKind::kOpen);
  EXPECT_DOUBLE_EQ(vm.sensor(static_cast<std::size_t>(nut)).Latest().temp_c, 50.0);
  // A time already past applies at once; the other sensors are untouched.
  ASSERT_TRUE(vm.ScheduleSensorFault("x_bearing", SensorFault{SensorFaultKind::kStuck}, 0));
  EXPECT_EQ(vm.sensor(static_cast<std::size_t>(vm.SensorIndex("x_bearing"))).fault().kind, SensorFaultKind::kStuck);
  EXPECT_EQ(vm.sensor(static_cast<std::size_t>(vm.SensorIndex("y_nut"))).fault().kind, SensorFaultKind::kNone);
}

}  // namespace
}  // namespace trueaxis::sim
