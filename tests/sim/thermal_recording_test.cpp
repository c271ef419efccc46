// The thermal-drift recording of the virtual machine: what it logs is what the machine did.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/thermal_recording.hpp"

namespace trueaxis::sim {
namespace {

MachineDescription Vmc850() {
  return ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
}

TEST(ThermalRecording, LogsEverySensorAndTheTrueErrorOnTheGrid) {
  VirtualMachine vm(Vmc850(), 5);
  ThermalRecordingOptions o;
  o.hours = 6;
  o.interval_s = 120;
  o.programme_seed = 5;
  const ThermalRecording rec = RecordThermalDay(vm, o);
  ASSERT_EQ(rec.time_s.size(), 181u);  // 6 h every 2 min, both ends
  EXPECT_EQ(rec.sensor_names.size(), vm.SensorCount());
  ASSERT_EQ(rec.error_names.size(), 3u);
  EXPECT_EQ(rec.error_names[0], "X_at_638mm");  // 0.75 of the 850 mm travel
  for (std::size_t r = 1; r < rec.time_s.size(); ++r) ASSERT_GT(rec.time_s[r], rec.time_s[r - 1]);
  // The last row's error is the machine's own true error at that position now.
  const auto last = static_cast<Eigen::Index>(rec.time_s.size() - 1);
  EXPECT_NEAR(rec.errors_um(last, 0), vm.ErrorAtUm(0, 637.5, +1), 0.5);
  // The day has machining in it: the X nut warms and the X error drifts by micrometres.
  const Eigen::Index nut = 0;
  ASSERT_EQ(rec.sensor_names[0], "x_nut");
  EXPECT_GT(rec.temperatures_c.col(nut).maxCoeff() - rec.temperatures_c(0, nut), 0.5);
  EXPECT_GT(rec.errors_um.col(0).maxCoeff() - rec.errors_um.col(0).minCoeff(), 3.0);
  EXPECT_FALSE(rec.programme.empty());
}

TEST(ThermalRecording, TheSeedDrawsTheDay) {
  ThermalRecordingOptions o;
  o.hours = 4;
  o.programme_seed = 1;
  VirtualMachine a(Vmc850(), 1), b(Vmc850(), 1), c(Vmc850(), 1);
  const auto ra = RecordThermalDay(a, o), rb = RecordThermalDay(b, o);
  o.programme_seed = 2;
  const auto rc = RecordThermalDay(c, o);
  EXPECT_EQ(ra.programme, rb.programme);
  EXPECT_EQ(ra.errors_um, rb.errors_um);
  EXPECT_NE(ra.programme, rc.programme);
}

TEST(ThermalRecording, BadOptionsAreRefused) {
  VirtualMachine vm(Vmc850(), 1);
  ThermalRecordingOptions o;
  o.interval_s = 0;
  EXPECT_THROW(RecordThermalDay(vm, o), InputError);
  o = {};
  o.position_fraction = 1.5;
  EXPECT_THROW(RecordThermalDay(vm, o), InputError);
  o = {};
  o.hours = 0.01;  // fewer than 10 samples
  EXPECT_THROW(RecordThermalDay(vm, o), InputError);
}

}  // namespace
}  // namespace trueaxis::sim
