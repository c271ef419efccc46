#include "trueaxis/signal/monitored_temperature_source.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "support/mock_hardware.hpp"
#include "synthetic.hpp"

namespace trueaxis::signal {
namespace {

// The shared mock hardware as a scripted source: values set by the test, optional link failure.
struct ScriptedSource : trueaxis::testing::MockTemperatures {
  ScriptedSource() : MockTemperatures({"ambient", "x_nut"}, 20.0) { values[1].temp_c = 25.0; }
};

TEST(MonitoredTemperatureSource, DeliversFilteredCalibratedValuesAndFlagsFaults) {
  ScriptedSource inner;
  double now = 0;
  MonitoredTemperatureSource source(inner, {}, [&now] { return now; });
  ASSERT_EQ(source.ChannelCount(), 2u);
  EXPECT_EQ(source.ChannelName(1), "x_nut");
  source.monitor().SetCalibration(1, {1.0, -0.5});
  std::vector<JudgedTemperature> out(2);
  testing::NoisySensor noise;
  for (int i = 0; i < 600; ++i, now += 0.1) {
    inner.values[1] = {noise.Sample(25.0), false};
    ASSERT_TRUE(source.Read(out));
  }
  EXPECT_TRUE(out[1].usable());
  EXPECT_NEAR(out[1].value_c, 24.5, 0.1);  // calibrated and filtered
  EXPECT_DOUBLE_EQ(out[0].value_c, 20.0);
  const double good = out[1].value_c;
  // Open sensor: judged over_range (no value to use); the monitor keeps the last good one.
  inner.values[1] = {500.0, false};
  for (int i = 0; i < 5; ++i, now += 0.1) source.Read(out);
  EXPECT_FALSE(out[1].usable());
  EXPECT_EQ(out[1].status, ChannelStatus::kOverRange);
  EXPECT_DOUBLE_EQ(out[1].raw_c, 500.0);
  EXPECT_TRUE(std::isnan(out[1].value_c));
  EXPECT_NEAR(source.monitor().reading(1).last_good_c, good, 0.05);
  EXPECT_EQ(source.monitor().reading(1).status, ChannelStatus::kOverRange);
  // Link loss: Read() false, out untouched; after stale_after_s the monitor says no_data.
  inner.fail = true;
  const auto before = out;
  EXPECT_FALSE(source.Read(out));
  EXPECT_EQ(out[0].value_c, before[0].value_c);
  now += 5;
  EXPECT_FALSE(source.Read(out));
  EXPECT_EQ(source.monitor().reading(0).status, ChannelStatus::kNoData);
}

// A 0–50 °C transmitter (seed 000's Pt100 chain) cannot tell 50 °C from 70 °C: at its rail the
// reading is not a temperature, though it lies well inside the plausible limits (−10…80 °C).
TEST(MonitoredTemperatureSource, AReadingAtTheMeasuringChainsRailIsAFault) {
  ScriptedSource inner;
  inner.ranges = {hw::MeasuringRange{}, hw::MeasuringRange{0.0, 50.0}};
  double now = 0;
  MonitoredTemperatureSource source(inner, {}, [&now] { return now; });
  std::vector<JudgedTemperature> out(2);
  auto run = [&](double x_nut_c, int samples) {
    for (int i = 0; i < samples; ++i, now += 1.0) {
      inner.values[1].temp_c = x_nut_c;
      inner.values[0].temp_c = 20.0 + 0.01 * (i % 3);  // the other channel moves (not "stuck")
      source.Read(out);
    }
  };
  // The nut warms slowly towards the rail: a good reading just below it.
  for (double t = 25.0; t <= 49.5; t += 0.05) run(t, 1);
  EXPECT_EQ(source.monitor().reading(1).status, ChannelStatus::kOk);
  EXPECT_TRUE(out[1].usable());
  // Pinned at the transmitter's rail: over_range, the last good value kept below the rail.
  run(50.0, 5);
  EXPECT_EQ(source.monitor().reading(1).status, ChannelStatus::kOverRange);
  EXPECT_EQ(out[1].status, ChannelStatus::kOverRange);
  EXPECT_LT(source.monitor().reading(1).last_good_c, 49.9);
  // The same reading from a channel whose range is not known is a temperature.
  inner.ranges.clear();
  run(50.0, 30);  // recover_samples (20) clean samples return it to ok
  EXPECT_EQ(source.monitor().reading(1).status, ChannelStatus::kOk);
  // The rail at the low end: a transmitter at 0 V (broken loop) is under_range.
  inner.ranges = {hw::MeasuringRange{}, hw::MeasuringRange{0.0, 50.0}};
  run(0.0, 5);
  EXPECT_EQ(source.monitor().reading(1).status, ChannelStatus::kUnderRange);
}

TEST(MonitoredTemperatureSource, ReadAllocatesNothing) {
  ScriptedSource inner;
  double now = 0;
  MonitoredTemperatureSource source(inner, {}, [&now] { return now; });
  std::vector<JudgedTemperature> out(2);
  for (int i = 0; i < 10; ++i, now += 0.01) source.Read(out);
  const long before = trueaxis::testing::AllocationCount();
  for (int i = 0; i < 5000; ++i, now += 0.01) {
    inner.fail = i % 100 == 0;
    source.Read(out);
  }
  EXPECT_EQ(trueaxis::testing::AllocationCount() - before, 0);
}

}  // namespace
}  // namespace trueaxis::signal
