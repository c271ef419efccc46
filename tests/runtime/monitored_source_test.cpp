// The one temperature pipeline (signal::MonitoredTemperatureSource) in front of the compensator.
#include "trueaxis/signal/monitored_temperature_source.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;
using signal::MonitoredTemperatureSource;

TEST(SignalChainInFrontOfTheCompensator, FiltersSpikesAndFlagsFaultsForTheCompensator) {
  MockTemperatures raw({"ambient", "nut", "bearing"}, 20.0);
  double now = 0;
  MonitoredTemperatureSource mon(raw, signal::MonitorOptions{}, [&] { return now; });
  MockCnc cnc({"X"});
  cnc.axes[0] = {400, +1, true};
  CompensatorOptions o;
  o.shaper.max_step_um = 1000;
  auto comp = Compensator::ForHardware(o, cnc, mon, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  auto cycle = [&](int n) {
    for (int i = 0; i < n; ++i) {
      now += 0.1;
      comp->RunCycle(cnc, mon, now);
    }
  };
  raw.Set("nut", 25);
  cycle(300);  // 30 s: the low-pass has settled
  const double settled = cnc.cnc_value_um[0];
  EXPECT_NEAR(comp->LastStatus().channels[1].value_c, 25, 0.05);
  // A single-sample spike of +8 °C: rejected by the Hampel filter, the output does not move.
  raw.Set("nut", 33);
  cycle(1);
  raw.Set("nut", 25);
  cycle(20);
  EXPECT_NEAR(cnc.cnc_value_um[0], settled, 1.0);
  // An open RTD (device flag): the monitor reports it, the compensator holds the last good value.
  raw.SetFault("nut", true);
  raw.Set("nut", 50);
  cycle(10);
  EXPECT_TRUE(comp->LastStatus().alarms & kAlarmSensorHeld);
  EXPECT_NEAR(cnc.cnc_value_um[0], settled, 1.0);
  EXPECT_NE(mon.monitor().reading(1).status, signal::ChannelStatus::kOk);
}

TEST(SignalChainInFrontOfTheCompensator, SourceFailureIsPassedOn) {
  MockTemperatures raw({"nut"}, 20.0);
  double now = 0;
  MonitoredTemperatureSource mon(raw, signal::MonitorOptions{}, [&] { return now; });
  std::vector<signal::JudgedTemperature> out(1);
  EXPECT_TRUE(mon.Read(out));
  raw.fail = true;
  now = 1;
  EXPECT_FALSE(mon.Read(out));
}

}  // namespace
}  // namespace trueaxis::runtime
