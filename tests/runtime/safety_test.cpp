// Machine-side safety (MISSION M6): whatever happens to sensors, the link,
// the enable switches or the model, the value the CNC holds is bounded and
// changes by at most the step limit per cycle.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

constexpr double kStep = 0.5;
constexpr double kBound = 60;

CompensatorOptions SafeOptions() {
  CompensatorOptions o;
  o.shaper.max_step_um = kStep;
  o.shaper.max_correction_um = kBound;
  o.sensor.hold_last_good_s = 5;
  return o;
}

// Drives a compensator and checks the invariants on every cycle, on the
// values the CNC actually holds (successful writes only).
// `judged`: the raw readings go through the temperature judge (as in `run`); else the mock's own
// verdicts (a flagged channel is faulty) reach the step.
struct Harness {
  explicit Harness(CompensatorOptions o = SafeOptions(), std::vector<AxisInterface> ifaces = {}, bool judged = false)
      : cnc({"X", "Y"}), temps({"ambient", "nut", "bearing"}, 20.0) {
    if (judged) {
      signal::MonitorOptions mo;
      mo.faults = o.sensor.judge;
      judge = std::make_unique<signal::MonitoredTemperatureSource>(temps, mo, [this] { return t; });
    }
    comp = Compensator::ForHardware(o, cnc, Source(), ifaces);
    for (std::size_t i = 0; i < 2; ++i) {
      const auto& a = comp->axes()[i];
      limit[i] = std::max(a.PhysicalQuantumUm(), kStep) * a.CncScale() + 1e-9;
      bound[i] = kBound * a.CncScale() + 1e-9;
    }
    prev = cnc.cnc_value_um;
  }
  const CycleStatus& Cycle(int n = 1) {
    const CycleStatus* s = nullptr;
    for (int k = 0; k < n; ++k) {
      t += 0.01;
      s = &comp->RunCycle(cnc, Source(), t);
      for (std::size_t i = 0; i < 2; ++i) {
        const double d = std::fabs(cnc.cnc_value_um[i] - prev[i]);
        max_delta[i] = std::max(max_delta[i], d);
        EXPECT_LE(d, limit[i]) << "axis " << i << " jumped at t=" << t;
        EXPECT_LE(std::fabs(cnc.cnc_value_um[i]), bound[i]);
        prev[i] = cnc.cnc_value_um[i];
      }
      alarms_seen |= s->alarms;
    }
    return *s;
  }
  signal::JudgedTemperatureSource& Source() {
    if (judge) return *judge;
    return temps;
  }
  MockCnc cnc;
  MockTemperatures temps;
  std::unique_ptr<signal::MonitoredTemperatureSource> judge;
  std::unique_ptr<Compensator> comp;
  double t = 0;
  double limit[2], bound[2];
  double max_delta[2] = {0, 0};
  std::vector<double> prev;
  std::uint32_t alarms_seen = 0;
};

// Warm machine, X at 450 mm: the thermal part is large.
void WarmUp(Harness& h) {
  h.comp->PublishModel(TestModel(), "A");
  h.cnc.axes[0] = {450, +1, true};
  h.cnc.axes[1] = {50, -1, true};
  h.temps.Set("nut", 30);
  h.temps.Set("bearing", 25);
  h.temps.Set("ambient", 21);
  h.Cycle(400);
}

TEST(Safety, SensorFaultHoldsLastGoodThenFallsBackToGeometricSmoothly) {
  Harness h;
  WarmUp(h);
  const double full = h.cnc.cnc_value_um[0];
  const double thermal = h.comp->LastStatus().axes[0].prediction.thermal_um;
  ASSERT_GT(std::fabs(thermal), 20);  // a fallback really changes the output
  h.temps.SetFault("nut", true);
  const auto& s1 = h.Cycle(100);  // 1 s < 5 s hold
  EXPECT_TRUE(s1.alarms & kAlarmSensorHeld);
  EXPECT_FALSE(s1.alarms & kAlarmSensorFallback);
  EXPECT_EQ(s1.channels[1].health, ChannelHealth::kHeld);
  EXPECT_DOUBLE_EQ(h.cnc.cnc_value_um[0], full);  // last good value: nothing changes
  const auto& s2 = h.Cycle(600);  // past the hold time
  EXPECT_TRUE(s2.alarms & kAlarmSensorFallback);
  EXPECT_FALSE(s2.axes[0].thermal_used);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], -s2.axes[0].prediction.geometric_um, 0.75 + 1e-9);
  EXPECT_GT(std::fabs(h.cnc.cnc_value_um[0] - full), 20);
  h.temps.SetFault("nut", false);  // sensor repaired: back to the full model, ramped
  const auto& s3 = h.Cycle(300);
  EXPECT_EQ(s3.alarms, 0u) << AlarmNames(s3.alarms);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], full, 1.0);
  EXPECT_GT(h.max_delta[0], 0.4);  // the ramps ran at the limit, not slower by accident
}

// Implausible readings never reach the model: the temperature judge in front rejects them (each
// rule once) and the step holds the last good value.
TEST(Safety, NanSpikeAndJumpReadingsAreRejected) {
  Harness h(SafeOptions(), {}, /*judged=*/true);
  WarmUp(h);
  h.Cycle(3000);  // 30 s more: the judge's low-pass has settled at 30 °C
  const double full = h.cnc.cnc_value_um[0];
  const double nut_c = h.comp->LastStatus().channels[1].value_c;
  ASSERT_NEAR(nut_c, 30, 0.01);
  constexpr std::uint32_t kSensor = kAlarmSensorHeld | kAlarmSensorFallback;
  h.temps.Set("nut", std::nan(""));  // not a number: hardware_fault
  const auto& s0 = h.Cycle(10);
  EXPECT_EQ(s0.channels[1].health, ChannelHealth::kHeld);
  EXPECT_EQ(s0.alarms & kSensor, kAlarmSensorHeld);
  EXPECT_DOUBLE_EQ(h.cnc.cnc_value_um[0], full);
  h.temps.Set("nut", 30);
  EXPECT_EQ(h.Cycle(30).channels[1].health, ChannelHealth::kOk);  // after the judge's 20 clean samples
  h.temps.Set("nut", 80);  // one sample 50 °C off: a spike, rejected by the filter — no alarm
  h.Cycle(1);
  h.temps.Set("nut", 30);
  const auto& s1 = h.Cycle(10);
  EXPECT_EQ(h.alarms_seen & kSensor, kAlarmSensorHeld);  // only the NaN's
  EXPECT_EQ(s1.channels[1].health, ChannelHealth::kOk);
  EXPECT_NEAR(s1.channels[1].value_c, nut_c, 0.01);
  EXPECT_GE(h.judge->monitor().SpikeCount(1), 1u);
  h.temps.Set("nut", 500);  // out of range (open RTD)
  const auto& s2 = h.Cycle(10);
  EXPECT_EQ(h.judge->monitor().reading(1).status, signal::ChannelStatus::kOverRange);
  EXPECT_EQ(s2.channels[1].health, ChannelHealth::kHeld);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], full, 1.0);
  h.temps.Set("nut", 30);
  EXPECT_EQ(h.Cycle(30).channels[1].health, ChannelHealth::kOk);
  h.temps.Set("nut", 80);  // a 50 °C jump that stays: faster than any structure, rate_of_change
  const auto& s3 = h.Cycle(20);
  EXPECT_EQ(h.judge->monitor().reading(1).status, signal::ChannelStatus::kRateOfChange);
  EXPECT_EQ(s3.channels[1].health, ChannelHealth::kHeld);
  EXPECT_NEAR(s3.channels[1].value_c, nut_c, 1.0);  // what crept through before it was confirmed
  EXPECT_NEAR(h.cnc.cnc_value_um[0], full, 2.0);
}

TEST(Safety, ZeroFallbackRampsTheAxisToZero) {
  auto o = SafeOptions();
  o.sensor.fallback = SensorFallback::kZero;
  o.sensor.hold_last_good_s = 0;
  Harness h(o);
  WarmUp(h);
  ASSERT_GT(std::fabs(h.cnc.cnc_value_um[0]), 10);
  h.temps.SetFault("bearing", true);
  h.Cycle(400);
  EXPECT_EQ(h.cnc.cnc_value_um[0], 0);
  EXPECT_EQ(h.cnc.cnc_value_um[1], 0);
}

TEST(Safety, TemperatureSourceLossFallsBack) {
  Harness h;
  WarmUp(h);
  h.temps.fail = true;
  const auto& s = h.Cycle(700);
  EXPECT_TRUE(s.alarms & kAlarmTemperatureSource);
  EXPECT_TRUE(s.alarms & kAlarmSensorFallback);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], -s.axes[0].prediction.geometric_um, 0.75 + 1e-9);
}

TEST(Safety, LinkLossHoldKeepsTheValueAndRecoveryRampsBack) {
  Harness h;
  WarmUp(h);
  const double held = h.cnc.cnc_value_um[0];
  h.cnc.fail_read = true;
  h.cnc.axes[0].position_mm = 0;  // the machine moves while we are blind
  const auto& s = h.Cycle(200);
  EXPECT_TRUE(s.alarms & kAlarmLinkRead);
  EXPECT_DOUBLE_EQ(h.cnc.cnc_value_um[0], held);
  h.cnc.fail_read = false;
  h.Cycle(2);  // recovery needs 3 good reads in a row
  EXPECT_DOUBLE_EQ(h.cnc.cnc_value_um[0], held);
  h.Cycle(400);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], h.comp->LastStatus().axes[0].desired_um, 0.75 + 1e-9);
  EXPECT_GT(std::fabs(h.cnc.cnc_value_um[0] - held), 20);
}

TEST(Safety, LinkLossRampToZeroUsesTheWritesThatGetThrough) {
  auto o = SafeOptions();
  o.link_loss = LinkLossPolicy::kRampToZero;
  Harness h(o);
  WarmUp(h);
  ASSERT_GT(std::fabs(h.cnc.cnc_value_um[0]), 20);
  h.cnc.fail_read = true;  // reads time out, writes still arrive
  h.Cycle(300);
  EXPECT_EQ(h.cnc.cnc_value_um[0], 0);
  h.cnc.fail_read = false;
  h.Cycle(400);
  EXPECT_GT(std::fabs(h.cnc.cnc_value_um[0]), 20);
}

TEST(Safety, TotalLinkLossNeverJumpsOnRecovery) {
  auto o = SafeOptions();
  o.link_loss = LinkLossPolicy::kRampToZero;
  Harness h(o);
  WarmUp(h);
  const double held = h.cnc.cnc_value_um[0];
  h.cnc.fail_read = true;
  h.cnc.fail_write = true;
  const auto& s = h.Cycle(300);
  EXPECT_TRUE(s.alarms & kAlarmLinkWrite);
  EXPECT_DOUBLE_EQ(h.cnc.cnc_value_um[0], held);  // the CNC keeps what it had
  h.cnc.fail_write = false;  // writes back first, reads still failing: ramp from the held value
  h.Cycle(5);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], held, 5 * kStep + 1.0);
  h.cnc.fail_read = false;
  h.Cycle(500);
}

TEST(Safety, EnableDisableRamps) {
  Harness h;
  WarmUp(h);
  const double full = h.cnc.cnc_value_um[0];
  h.comp->SetEnabled(false);
  h.Cycle(10);
  EXPECT_NE(h.cnc.cnc_value_um[0], 0);  // still ramping, not switched off at once
  h.Cycle(300);
  EXPECT_EQ(h.cnc.cnc_value_um[0], 0);
  h.comp->SetEnabled(true);
  h.Cycle(300);
  EXPECT_NEAR(h.cnc.cnc_value_um[0], full, 1.0);
  h.comp->SetAxisEnabled(0, false);
  h.Cycle(300);
  EXPECT_EQ(h.cnc.cnc_value_um[0], 0);
  EXPECT_NE(h.cnc.cnc_value_um[1], 0);  // the other axis carries on
  h.comp->SetAxisEnabled(0, true);
  h.cnc.machine.compensation_enabled = false;  // the CNC-side switch
  h.Cycle(300);
  EXPECT_EQ(h.cnc.cnc_value_um[0], 0);
  EXPECT_EQ(h.cnc.cnc_value_um[1], 0);
}

TEST(Safety, ModelSwapRampsAndReleasesTheOldModelOffTheLoop) {
  Harness h;
  auto a = TestModel(1.0);
  std::weak_ptr<const model::CompositeModel> weak_a = a;
  h.comp->PublishModel(std::move(a), "A");
  h.cnc.axes[0] = {450, +1, true};
  h.Cycle(200);
  const auto id_a = h.comp->LastStatus().model_id;
  const double with_a = h.cnc.cnc_value_um[0];
  h.comp->PublishModel(TestModel(4.0), "B");  // very different geometry
  const auto& s = h.Cycle(1);
  EXPECT_NE(s.model_id, id_a);
  EXPECT_FALSE(weak_a.expired());  // retired, not freed by the loop
  h.comp->CollectRetired();
  EXPECT_TRUE(weak_a.expired());
  h.Cycle(400);
  EXPECT_GT(std::fabs(h.cnc.cnc_value_um[0] - with_a), 10);
}

TEST(Safety, RandomisedDayStaysBoundedAndSmooth) {
  AxisInterface y;
  y.axis = "Y";
  y.programming = Programming::kDiameter;
  y.pulse_equivalent_um = 0.5;
  for (auto policy : {LinkLossPolicy::kHold, LinkLossPolicy::kRampToZero}) {
    auto o = SafeOptions();
    o.link_loss = policy;
    Harness h(o, {y});
    std::shared_ptr<const model::CompositeModel> models[3] = {TestModel(1.0), TestModel(-2.0), TestModel(5.0)};
    h.comp->PublishModel(models[0], "m0");
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    double x = 0, vx = 0.5, y_pos = 100;
    for (int c = 0; c < 60000; ++c) {
      // motion: X sweeps back and forth, Y jitters
      x += vx;
      if (x > 500 || x < 0) vx = -vx;
      y_pos += (u(rng) - 0.5) * 2;
      h.cnc.axes[0] = {x, vx > 0 ? 1 : -1, true};
      h.cnc.axes[1] = {y_pos, u(rng) < 0.5 ? 0 : (u(rng) < 0.5 ? 1 : -1), true};
      // temperatures drift, with occasional garbage
      h.temps.Set("nut", 20 + 15 * std::sin(c * 1e-4) + (u(rng) < 0.001 ? 300 : 0));
      h.temps.Set("bearing", 20 + 5 * std::sin(c * 2e-4));
      h.temps.Set("ambient", u(rng) < 0.0005 ? std::nan("") : 20 + 2 * std::sin(c * 5e-5));
      if (u(rng) < 0.0005) h.temps.SetFault("nut", u(rng) < 0.5);
      if (u(rng) < 0.0005) h.cnc.fail_read = !h.cnc.fail_read;
      h.cnc.fail_write = u(rng) < 0.01;
      if (u(rng) < 0.0003) h.cnc.machine.coolant = u(rng) < 0.5 ? CoolantState::kOff : CoolantState::kFlood;
      if (u(rng) < 0.0002) h.comp->SetEnabled(u(rng) < 0.7);
      if (u(rng) < 0.0002) h.comp->PublishModel(models[static_cast<int>(u(rng) * 3) % 3], "swap");
      h.Cycle();
    }
    EXPECT_LE(h.max_delta[0], h.limit[0]);
    EXPECT_LE(h.max_delta[1], h.limit[1]);
    EXPECT_GT(h.max_delta[0], 0.3);  // the run really exercised the limiter
    EXPECT_TRUE(h.alarms_seen & kAlarmLinkRead);
    EXPECT_TRUE(h.alarms_seen & kAlarmLinkWrite);
    EXPECT_TRUE(h.alarms_seen & kAlarmSensorHeld);
  }
}

}  // namespace
}  // namespace trueaxis::runtime
