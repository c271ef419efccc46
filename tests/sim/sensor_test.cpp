// Sensor chains: quantisation of each converter, imperfections, faults.
#include <cmath>

#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/sim/virtual_machine.hpp"
#include "trueaxis/sim/virtual_sensor.hpp"

namespace trueaxis::sim {
namespace {

SensorDescription Desc(SensorKind kind, double offset = 0, double gain = 0, double noise = 0, double tau = 0) {
  SensorDescription d;
  d.name = "s";
  d.kind = kind;
  d.location = "ambient";
  d.offset_c = offset;
  d.gain_error = gain;
  d.noise_c = noise;
  d.time_constant_s = tau;
  return d;
}

bool OnGrid(double v, double step, double origin = 0) {
  const double k = (v - origin) / step;
  return std::abs(k - std::round(k)) < 1e-6;
}

TEST(Sensor, Ds18b20ReadsInSixteenthsOfADegree) {
  VirtualSensor s(Desc(SensorKind::kDs18b20, 0, 0, 0.02), 1, 20);
  for (int i = 0; i < 200; ++i) {
    s.Sample(20 + i * 0.0137, 1, i);
    const auto r = s.Latest();
    ASSERT_FALSE(r.hardware_fault);
    EXPECT_TRUE(OnGrid(r.temp_c, 0.0625)) << r.temp_c;
    EXPECT_NEAR(r.temp_c, 20 + i * 0.0137, 0.0625 / 2 + 0.1);
  }
}

TEST(Sensor, Pt100TransmitterAdcHasTwelveBitSteps) {
  const double step = 50.0 / 4095.0;
  EXPECT_DOUBLE_EQ(SensorStepC(SensorKind::kPt100Adc), step);
  VirtualSensor s(Desc(SensorKind::kPt100Adc), 1, 20);
  // A slow ramp without noise: every reading is a count of the ADC, and the
  // readings step by exactly one count.
  double prev = NAN;
  int steps = 0;
  for (int i = 0; i < 1000; ++i) {
    s.Sample(20 + i * 0.001, 1, i);
    const double v = s.Latest().temp_c;
    EXPECT_TRUE(OnGrid(v, step)) << v;
    if (!std::isnan(prev) && v != prev) {
      EXPECT_NEAR(v - prev, step, 1e-9);
      ++steps;
    }
    prev = v;
  }
  EXPECT_GE(steps, 75);  // 1 °C / 0.0122 °C ≈ 82 counts
  // Range of the transmitter: clamps at 0 and 50 °C, with no flag — so the chain's measuring
  // range is what the temperature pipeline needs to see that 50.0 is a rail, not a temperature.
  s.Sample(80, 1, 1001);
  EXPECT_DOUBLE_EQ(s.Latest().temp_c, 50.0);
  EXPECT_FALSE(s.Latest().hardware_fault);
  EXPECT_DOUBLE_EQ(SensorMeasuringRange(SensorKind::kPt100Adc).max_c, s.Latest().temp_c);
  EXPECT_DOUBLE_EQ(SensorMeasuringRange(SensorKind::kPt100Adc).min_c, 0.0);
}

TEST(Sensor, EveryKindReportsItsMeasuringRangeThroughTheMachine) {
  MachineDescription md = testing::TestMachine();
  md.sensors.clear();
  const SensorKind kinds[] = {SensorKind::kPt100Adc, SensorKind::kDs18b20, SensorKind::kRtdModule};
  const char* names[] = {"x_nut", "x_bearing", "ambient"};
  for (int i = 0; i < 3; ++i) {
    SensorDescription d = Desc(kinds[i]);
    d.name = names[i];
    d.location = names[i];
    md.sensors.push_back(d);
  }
  VirtualMachine vm(md, 1);
  ASSERT_EQ(vm.ChannelCount(), 3u);
  EXPECT_DOUBLE_EQ(vm.ChannelMeasuringRange(0).max_c, 50.0);   // 0–50 °C transmitter
  EXPECT_DOUBLE_EQ(vm.ChannelMeasuringRange(1).min_c, -55.0);  // DS18B20 datasheet
  EXPECT_DOUBLE_EQ(vm.ChannelMeasuringRange(1).max_c, 125.0);
  EXPECT_DOUBLE_EQ(vm.ChannelMeasuringRange(2).max_c, 150.0);  // ADAM-6015 default Pt100 range
}

TEST(Sensor, RtdModuleQuantisesFinelyAndFlagsOverRange) {
  VirtualSensor s(Desc(SensorKind::kRtdModule), 1, 20);
  s.Sample(23.4567, 1, 0);
  EXPECT_TRUE(OnGrid(s.Latest().temp_c, 200.0 / 65535.0, -50));
  EXPECT_NEAR(s.Latest().temp_c, 23.4567, 0.002);
  s.Sample(400, 1, 1);
  EXPECT_TRUE(s.Latest().hardware_fault);
}

TEST(Sensor, OffsetGainAndLagAreApplied) {
  VirtualSensor s(Desc(SensorKind::kRtdModule, 0.3, 0.01, 0, 20), 1, 20);
  s.Sample(20, 1, 0);
  EXPECT_NEAR(s.Latest().temp_c, 20 * 1.01 + 0.3, 0.002);
  // Step to 30 °C: after one time constant the probe is 63 % of the way.
  for (int i = 0; i < 20; ++i) s.Sample(30, 1, i);
  EXPECT_NEAR(s.ProbeC(), 20 + 10 * (1 - std::exp(-1.0)), 1e-6);
}

TEST(Sensor, FaultsShowLikeTheRealHardware) {
  VirtualSensor adc(Desc(SensorKind::kPt100Adc), 1, 22);
  adc.SetFault({SensorFaultKind::kOpen}, 0);
  adc.Sample(22, 1, 1);
  EXPECT_DOUBLE_EQ(adc.Latest().temp_c, 50.0);   // burn-out: up-scale, no flag
  EXPECT_FALSE(adc.Latest().hardware_fault);
  adc.SetFault({SensorFaultKind::kShort}, 1);
  adc.Sample(22, 1, 2);
  EXPECT_DOUBLE_EQ(adc.Latest().temp_c, 0.0);

  VirtualSensor ds(Desc(SensorKind::kDs18b20), 1, 22);
  ds.SetFault({SensorFaultKind::kOpen}, 0);
  ds.Sample(22, 1, 1);
  EXPECT_TRUE(ds.Latest().hardware_fault);
  ds.SetFault({SensorFaultKind::kShort}, 1);
  ds.Sample(22, 1, 2);
  EXPECT_DOUBLE_EQ(ds.Latest().temp_c, 85.0);   // power-on reset value

  VirtualSensor rtd(Desc(SensorKind::kRtdModule), 1, 22);
  rtd.SetFault({SensorFaultKind::kOpen}, 0);
  rtd.Sample(22, 1, 1);
  EXPECT_TRUE(rtd.Latest().hardware_fault);

  // Stuck: the value stops following the temperature.
  VirtualSensor st(Desc(SensorKind::kRtdModule), 1, 22);
  st.Sample(22, 1, 0);
  const double before = st.Latest().temp_c;
  st.SetFault({SensorFaultKind::kStuck}, 1);
  st.Sample(27, 1, 2);
  EXPECT_DOUBLE_EQ(st.Latest().temp_c, before);
  st.SetFault({}, 3);
  st.Sample(27, 1, 4);
  EXPECT_NEAR(st.Latest().temp_c, 27, 0.01);

  // Drift: offset grows at the configured rate.
  VirtualSensor dr(Desc(SensorKind::kRtdModule), 1, 22);
  SensorFault f{SensorFaultKind::kDrift};
  f.drift_c_per_hour = 2;
  dr.SetFault(f, 0);
  dr.Sample(22, 1, 1800);
  EXPECT_NEAR(dr.Latest().temp_c, 23, 0.01);

  // Spikes: some samples jump by the amplitude, most do not.
  VirtualSensor sp(Desc(SensorKind::kRtdModule), 5, 22);
  SensorFault fs{SensorFaultKind::kSpikes};
  fs.spike_probability = 0.2;
  fs.spike_amplitude_c = 5;
  sp.SetFault(fs, 0);
  int spikes = 0;
  for (int i = 0; i < 500; ++i) {
    sp.Sample(22, 1, i);
    if (std::abs(sp.Latest().temp_c - 22) > 4) ++spikes;
  }
  EXPECT_GT(spikes, 60);
  EXPECT_LT(spikes, 140);
}

TEST(Sensor, MachineSensorsAreReadThroughTemperatureSource) {
  VirtualMachine vm(testing::TestMachine(), 1);
  hw::TemperatureSource& src = vm;
  ASSERT_EQ(src.ChannelCount(), 3u * 2 + 2);  // x/y nut, bearing, motor + ambient, bed
  EXPECT_EQ(src.ChannelName(0), "x_nut");
  EXPECT_GE(vm.SensorIndex("ambient"), 0);
  std::vector<hw::RawTemperature> raw(src.ChannelCount());
  ASSERT_TRUE(src.Read(raw));
  const int amb = vm.SensorIndex("ambient");
  EXPECT_NEAR(raw[amb].temp_c, vm.AmbientC(), 0.5);  // within the sensor's offset
  ASSERT_TRUE(vm.SetSensorFault("x_nut", {SensorFaultKind::kShort}));
  EXPECT_FALSE(vm.SetSensorFault("no_such", {SensorFaultKind::kShort}));
  vm.Advance(2);
  ASSERT_TRUE(src.Read(raw));
  EXPECT_DOUBLE_EQ(raw[0].temp_c, 0.0);  // pt100_adc short → down-scale
  vm.SetSensorFault("x_nut", {});
  vm.Advance(2);
  ASSERT_TRUE(src.Read(raw));
  EXPECT_GT(raw[0].temp_c, 10.0);
  vm.SetLinkFault(true);
  EXPECT_FALSE(src.Read(raw));
}

}  // namespace
}  // namespace trueaxis::sim
