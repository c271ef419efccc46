// The compensator feeds the model's lagged key temperatures (AxisModel::key_lag_s,
// model/thermal_lag.hpp) into Predict, restarting the lag on a model swap and after a lost sensor.
#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/model/thermal_lag.hpp"
#include "trueaxis/model/thermal_state.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestAxisModel;

std::shared_ptr<const model::CompositeModel> LaggedModel(double nut_tau_s, double bearing_tau_s) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  m->axes.back().key_lag_s = {nut_tau_s, bearing_tau_s};
  return m;
}

struct LagRig : testing::OneAxisRig {
  // The error the model predicts at the CNC's position for the given (lagged) key temperatures.
  double ExpectedDesired(const model::CompositeModel& m, double nut_c, double bearing_c) const {
    const double key[2] = {nut_c, bearing_c};
    model::ThermalState ts{std::span<const double>(key, 2), 20.0, CoolantState::kOff, true};
    return model::CorrectionUm(model::Predict(m.axes[0], 400, Direction::kForward, ts));
  }
};

TEST(CompensatorLag, KeyTemperaturesArePassedThroughTheFirstOrderLag) {
  LagRig r;
  const auto m = LaggedModel(100, 0);  // nut lagged by 100 s, bearing raw
  r.comp->PublishModel(m, "lag");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);  // the filter starts at the readings (20 °C)
  r.temps.Set("nut", 26);
  r.temps.Set("bearing", 23);
  const auto& s = r.comp->RunCycle(r.cnc, r.temps, 100.0);  // one step of Δt = τ
  const double nut_eff = 20 + 6 * (1 - std::exp(-1.0));
  EXPECT_NEAR(s.axes[0].desired_um, r.ExpectedDesired(*m, nut_eff, 23), 1e-9);
  // The raw reading would give a clearly different correction: the lag is really applied.
  EXPECT_GT(std::fabs(r.ExpectedDesired(*m, 26, 23) - s.axes[0].desired_um), 1.0);
  // Many small cycles converge on the reading.
  const CycleStatus* last = nullptr;
  for (int i = 1; i <= 2000; ++i) last = &r.comp->RunCycle(r.cnc, r.temps, 100.0 + i * 1.0);
  EXPECT_NEAR(last->axes[0].desired_um, r.ExpectedDesired(*m, 26, 23), 1e-6);
}

TEST(CompensatorLag, ZeroTauUsesTheRawReadingsExactly) {
  LagRig r;
  const auto m = LaggedModel(0, 0);
  r.comp->PublishModel(m, "no lag");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.Set("nut", 27.5);
  r.temps.Set("bearing", 21.25);
  const auto& s = r.comp->RunCycle(r.cnc, r.temps, 0.01);
  EXPECT_DOUBLE_EQ(s.axes[0].desired_um, r.ExpectedDesired(*m, 27.5, 21.25));
}

TEST(CompensatorLag, ModelSwapRestartsTheLagAtTheCurrentReadings) {
  LagRig r;
  r.comp->PublishModel(LaggedModel(1000, 1000), "slow");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.Set("nut", 25);
  r.temps.Set("bearing", 24);
  r.comp->RunCycle(r.cnc, r.temps, 10.0);  // lagged values still near 20 °C
  const auto fast = LaggedModel(50, 50);
  r.comp->PublishModel(fast, "swapped");
  const auto& s = r.comp->RunCycle(r.cnc, r.temps, 10.01);
  // A new model may have other keys or τ: its filter starts at the readings, not at the old state.
  EXPECT_NEAR(s.axes[0].desired_um, r.ExpectedDesired(*fast, 25, 24), 1e-9);
}

TEST(CompensatorLag, LostSensorRestartsTheLagWhenItReturns) {
  LagRig r;
  const auto m = LaggedModel(600, 600);
  r.comp->PublishModel(m, "lag");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.SetFault("nut", true);
  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);  // beyond hold_last_good_s (60 s)
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  EXPECT_FALSE(lost.axes[0].thermal_used);
  r.temps.SetFault("nut", false);
  r.temps.Set("nut", 24);
  r.temps.Set("bearing", 22);
  const auto& back = r.comp->RunCycle(r.cnc, r.temps, 100.01);
  EXPECT_TRUE(back.axes[0].thermal_used);
  // Restarted at the returned readings (no memory of the value before the loss).
  EXPECT_NEAR(back.axes[0].desired_um, r.ExpectedDesired(*m, 24, 22), 1e-9);
}

// A model without lag or loss takes AdvanceModelDynamics' inline path (no call into the model's
// observer); the key state must be what model::AdvanceThermalState gives, cycle by cycle, through
// good, lost (NaN) and returning readings, and a model with a lag must still take the observer.
TEST(CompensatorLag, KeyStateWithoutDynamicsIsWhatTheModelsAdvanceGives) {
  std::vector<AxisInterface> axes(2);
  axes[0].axis = "X";
  axes[1].axis = "Y";
  const std::vector<std::string> channels = {"ambient", "nut", "bearing"};
  auto plain = std::make_shared<model::CompositeModel>();
  plain->axes = {TestAxisModel("X"), TestAxisModel("Y")};
  plain->axes[1].key_loss_s[static_cast<std::size_t>(CoolantState::kFlood)] = {0.0, 0.0};  // zero: none
  const auto bound = BindModel(plain, "plain", axes, channels, {});
  bound->id = 1;
  ASSERT_FALSE(bound->axes[0].thermal_dynamics);
  ASSERT_FALSE(bound->axes[1].thermal_dynamics);
  EXPECT_TRUE(BindModel(LaggedModel(60, 0), "lagged", axes, channels, {})->axes[0].thermal_dynamics);

  ModelDynamics dyn;
  dyn.axes.resize(2);
  model::AxisThermalState reference[2];
  const double nan = std::nan("");
  const double series[][3] = {{20.0, 25.0, 21.0}, {20.1, 25.5, 21.2}, {20.1, nan, 21.3},
                              {20.2, 26.0, 21.3}, {20.2, 26.5, nan},  {20.3, 27.0, 21.5}};
  double t = 0;
  for (const auto& reading : series) {
    ChannelStatus st[3];
    for (int c = 0; c < 3; ++c) {
      st[c].value_c = reading[c];
      st[c].health = std::isnan(reading[c]) ? ChannelHealth::kLost : ChannelHealth::kOk;
    }
    t += 0.01;
    AdvanceModelDynamics(*bound, st, CoolantState::kFlood, t, dyn);
    for (std::size_t i = 0; i < 2; ++i) {
      const double keys[2] = {reading[1], reading[2]};
      model::AdvanceThermalState(plain->axes[i], reference[i], {keys, reading[0], CoolantState::kFlood}, 0.01);
      EXPECT_EQ(dyn.axes[i].thermal.valid, reference[i].valid) << "t=" << t;
      for (std::size_t k = 0; k < 2; ++k) {
        if (std::isnan(reference[i].key_c[k])) EXPECT_TRUE(std::isnan(dyn.axes[i].thermal.key_c[k]));
        else EXPECT_EQ(dyn.axes[i].thermal.key_c[k], reference[i].key_c[k]) << "t=" << t << " key " << k;
      }
    }
  }
}

}  // namespace
}  // namespace trueaxis::runtime
