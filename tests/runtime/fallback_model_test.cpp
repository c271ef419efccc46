// A lost key sensor hands the axis to the model's fallback fitted without it (AxisModel::fallbacks,
// docs/runtime.md "Sensor faults"): the fallback's prediction is used, with its own key state
// advanced alongside the model's, and the sensor_fallback alarm stays raised while it runs.
#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/thermal_state.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_step.hpp"

namespace trueaxis::runtime {
namespace {
using testing::TestAxisModel;

// X with keys nut + bearing (no lag) and one fallback on the bearing alone, with gains of its own
// so its correction is told apart from the full model's and from the geometric part.
model::AxisModel BearingOnlyFallback(double bearing_tau_s) {
  model::AxisModel f = TestAxisModel("X");
  f.key_sensors = {"bearing"};
  f.baseline_temp_c = {20};
  if (bearing_tau_s > 0) f.key_lag_s = {bearing_tau_s};
  for (auto& d : f.directions) d.thermal = {{CoolantState::kOff, {-0.025}, 0}};
  return f;
}

std::shared_ptr<const model::CompositeModel> ModelWithFallback(double bearing_tau_s) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  m->axes.back().fallbacks.push_back(BearingOnlyFallback(bearing_tau_s));
  return m;
}

// X with a fallback fitted without the room sensor (its keys the model's, gains of its own).
std::shared_ptr<const model::CompositeModel> ModelWithRoomFallback() {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  model::AxisModel no_room = TestAxisModel("X");
  no_room.ambient_sensor.clear();
  no_room.rho_um_per_mm_per_c = 0;
  for (auto& d : no_room.directions) d.thermal = {{CoolantState::kOff, {-0.015, -0.006}, 0}};
  m->axes.back().fallbacks.push_back(no_room);
  return m;
}

struct Rig : testing::OneAxisRig {
  using OneAxisRig::OneAxisRig;
  static double Desired(const model::AxisModel& a, std::vector<double> keys, double position_mm = 400,
                        Direction direction = Direction::kForward) {
    model::ThermalState ts{std::span<const double>(keys.data(), keys.size()), 20.0, CoolantState::kOff, true};
    return model::CorrectionUm(model::Predict(a, position_mm, direction, ts));
  }
  // Publishes `m`, runs a cycle with the nut at 26 °C and the bearing at 23 °C, then the nut faults:
  // held at 30 s, lost at 100 s. Returns the status of that cycle.
  const CycleStatus& LoseTheNut(const std::shared_ptr<const model::CompositeModel>& m, const char* label) {
    comp->PublishModel(m, label);
    temps.Set("nut", 26);
    temps.Set("bearing", 23);
    comp->RunCycle(cnc, temps, 0.0);
    temps.SetFault("nut", true);
    comp->RunCycle(cnc, temps, 30.0);  // held
    return comp->RunCycle(cnc, temps, 100.0);
  }
};

TEST(FallbackModel, TakesOverWhenAKeySensorIsLostAndHandsBackWhenItReturns) {
  Rig r;
  const auto m = ModelWithFallback(0);
  r.comp->PublishModel(m, "with fallback");
  r.temps.Set("nut", 26);
  r.temps.Set("bearing", 23);
  const auto& ok = r.comp->RunCycle(r.cnc, r.temps, 0.0);
  EXPECT_EQ(ok.axes[0].fallback_model, -1);
  EXPECT_NEAR(ok.axes[0].desired_um, Rig::Desired(m->axes[0], {26, 23}), 1e-9);

  r.temps.SetFault("nut", true);
  const auto& held = r.comp->RunCycle(r.cnc, r.temps, 30.0);  // within hold_last_good_s: the model, held value
  EXPECT_TRUE(held.alarms & kAlarmSensorHeld);
  EXPECT_EQ(held.axes[0].fallback_model, -1);

  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);  // beyond it: the fallback
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  EXPECT_TRUE(lost.axes[0].thermal_used);
  EXPECT_EQ(lost.axes[0].fallback_model, 0);
  const double fallback = Rig::Desired(m->axes[0].fallbacks[0], {23});
  EXPECT_NEAR(lost.axes[0].desired_um, fallback, 1e-9);
  // Neither the full model (with the last nut reading) nor the geometric part alone.
  EXPECT_GT(std::fabs(fallback - Rig::Desired(m->axes[0], {26, 23})), 1.0);
  model::ThermalState none{{}, std::nan(""), CoolantState::kOff, false};
  EXPECT_GT(std::fabs(fallback - model::CorrectionUm(model::Predict(m->axes[0], 400, Direction::kForward, none))), 1.0);

  r.temps.SetFault("nut", false);
  r.temps.Set("nut", 25);
  const auto& back = r.comp->RunCycle(r.cnc, r.temps, 100.01);
  EXPECT_EQ(back.axes[0].fallback_model, -1);
  EXPECT_FALSE(back.alarms & kAlarmSensorFallback);
  EXPECT_NEAR(back.axes[0].desired_um, Rig::Desired(m->axes[0], {25, 23}), 1e-9);
}

TEST(FallbackModel, ItsLagCarriesTheHistoryFromBeforeTheLoss) {
  Rig r;
  const double tau = 600;
  const auto m = ModelWithFallback(tau);
  r.comp->PublishModel(m, "lagged fallback");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);  // every state starts at 20 °C
  r.temps.Set("bearing", 26);
  for (int t = 1; t <= 300; ++t) r.comp->RunCycle(r.cnc, r.temps, t);
  r.temps.SetFault("nut", true);
  const CycleStatus* s = nullptr;
  for (int t = 301; t <= 400; ++t) s = &r.comp->RunCycle(r.cnc, r.temps, t);
  ASSERT_EQ(s->axes[0].fallback_model, 0);
  // The bearing's lagged value over 400 s of a step to 26 °C, not a restart at the reading.
  const double lagged = 26 - 6 * std::exp(-400 / tau);
  EXPECT_NEAR(s->axes[0].desired_um, Rig::Desired(m->axes[0].fallbacks[0], {lagged}), 1e-6);
  EXPECT_GT(std::fabs(Rig::Desired(m->axes[0].fallbacks[0], {26}) - s->axes[0].desired_um), 0.5);
}

// The ambient sensor lost: the fallback fitted without a room term (its keys read) takes over,
// instead of the model running on without its ρ term and with rises no longer above the room.
TEST(FallbackModel, ALostAmbientSensorHandsTheAxisToTheFallbackWithoutARoomTerm) {
  Rig r;
  const auto m = ModelWithRoomFallback();
  const model::AxisModel& no_room = m->axes[0].fallbacks[0];
  r.comp->PublishModel(m, "room fallback");
  r.temps.Set("ambient", 23);
  r.temps.Set("nut", 26);
  r.temps.Set("bearing", 24);
  EXPECT_EQ(r.comp->RunCycle(r.cnc, r.temps, 0.0).axes[0].fallback_model, -1);
  r.temps.SetFault("ambient", true);
  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  EXPECT_EQ(lost.axes[0].fallback_model, 0);
  std::vector<double> keys{26, 24};
  model::ThermalState ts{keys, std::nan(""), CoolantState::kOff, true};
  EXPECT_NEAR(lost.axes[0].desired_um, model::CorrectionUm(model::Predict(no_room, 400, Direction::kForward, ts)), 1e-9);
}

// The hand-over (SensorFaultPolicy::fallback_handover_s): the fallback starts from the model's last
// correction and the difference decays with τ — at every position and in both directions, since it
// is carried as the line the two thermal parts differ by — while the coolant state is the loss's.
TEST(FallbackModel, TakesOverFromTheModelsLastCorrectionAndTheDifferenceDecaysWithTau) {
  const double tau = 600;
  Rig r(tau);
  const auto m = ModelWithFallback(0);
  const model::AxisModel& fb = m->axes[0].fallbacks[0];
  // The cycle the nut is lost: no jump, the model's correction with the last nut reading.
  const auto& lost = r.LoseTheNut(m, "hand-over");
  ASSERT_EQ(lost.axes[0].fallback_model, 0);
  EXPECT_NEAR(lost.axes[0].desired_um, Rig::Desired(m->axes[0], {26, 23}), 1e-9);
  const auto carried = [&](double position_mm, Direction d) {
    return Rig::Desired(m->axes[0], {26, 23}, position_mm, d) - Rig::Desired(fb, {23}, position_mm, d);
  };
  ASSERT_GT(std::fabs(carried(400, Direction::kForward)), 1.0);  // the two models differ there
  // One τ later, with the bearing warmer and the axis elsewhere in reverse: the fallback's own
  // prediction for now plus the difference at the loss (at this position) times e^-1.
  r.temps.Set("bearing", 25);
  r.cnc.axes[0] = {100, -1, true};
  const auto& later = r.comp->RunCycle(r.cnc, r.temps, 100.0 + tau);
  ASSERT_EQ(later.axes[0].fallback_model, 0);
  EXPECT_NEAR(later.axes[0].desired_um,
              Rig::Desired(fb, {25}, 100, Direction::kReverse) + carried(100, Direction::kReverse) * std::exp(-1.0), 1e-9);
  // The flood on: the difference was taken with the dry gains and is no longer carried (the
  // fallback has no flood gains of its own and uses its dry ones).
  r.cnc.machine.coolant = CoolantState::kFlood;
  EXPECT_NEAR(r.comp->RunCycle(r.cnc, r.temps, 101.0 + tau).axes[0].desired_um,
              Rig::Desired(fb, {25}, 100, Direction::kReverse), 1e-9);
  r.cnc.machine.coolant = CoolantState::kOff;
  // Ten τ on: the fallback's own.
  const auto& settled = r.comp->RunCycle(r.cnc, r.temps, 100.0 + 10 * tau);
  EXPECT_NEAR(settled.axes[0].desired_um, Rig::Desired(fb, {25}, 100, Direction::kReverse), 1e-3);
  // The nut back: the model; lost again: a new hand-over from the model's correction then.
  r.temps.SetFault("nut", false);
  r.temps.Set("nut", 28);
  const double t_back = 100.0 + 11 * tau;
  EXPECT_NEAR(r.comp->RunCycle(r.cnc, r.temps, t_back).axes[0].desired_um,
              Rig::Desired(m->axes[0], {28, 25}, 100, Direction::kReverse), 1e-9);
  r.temps.SetFault("nut", true);
  r.comp->RunCycle(r.cnc, r.temps, t_back + 1);
  const auto& again = r.comp->RunCycle(r.cnc, r.temps, t_back + 100);
  ASSERT_EQ(again.axes[0].fallback_model, 0);
  EXPECT_NEAR(again.axes[0].desired_um, Rig::Desired(m->axes[0], {28, 25}, 100, Direction::kReverse), 1e-9);
}

// A lost room sensor: the hand-over starts from the model's correction with the last good room
// reading (the channel itself reads nothing any more).
TEST(FallbackModel, TheHandOverFromALostAmbientUsesTheLastGoodRoomReading) {
  const double tau = 900;
  Rig r(tau);
  const auto m = ModelWithRoomFallback();
  const model::AxisModel& no_room = m->axes[0].fallbacks[0];
  r.comp->PublishModel(m, "room fallback with hand-over");
  r.temps.Set("ambient", 23);
  r.temps.Set("nut", 26);
  r.temps.Set("bearing", 24);
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.SetFault("ambient", true);
  r.comp->RunCycle(r.cnc, r.temps, 30.0);  // held at 23 °C
  std::vector<double> keys{26, 24};
  const auto with_room = [&](double ambient_c) {
    model::ThermalState ts{keys, ambient_c, CoolantState::kOff, true};
    return model::CorrectionUm(model::Predict(m->axes[0], 400, Direction::kForward, ts));
  };
  model::ThermalState plain{keys, std::nan(""), CoolantState::kOff, true};
  const double fallback = model::CorrectionUm(model::Predict(no_room, 400, Direction::kForward, plain));
  ASSERT_GT(std::fabs(with_room(23) - fallback), 1.0);
  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);
  ASSERT_EQ(lost.axes[0].fallback_model, 0);
  EXPECT_NEAR(lost.axes[0].desired_um, with_room(23), 1e-9);
  const auto& later = r.comp->RunCycle(r.cnc, r.temps, 100.0 + tau);
  EXPECT_NEAR(later.axes[0].desired_um, fallback + (with_room(23) - fallback) * std::exp(-1.0), 1e-9);
}

// A key and the room sensor both lost: no fallback has all its sensors, so the one whose keys read
// goes on without its room term (as the model does when only its room sensor is lost), instead
// of the geometric part alone.
TEST(FallbackModel, AKeyAndTheRoomSensorLostLeaveTheFallbackWithoutItsRoomTerm) {
  Rig r;
  const auto m = ModelWithFallback(0);
  const model::AxisModel& fb = m->axes[0].fallbacks[0];
  ASSERT_EQ(fb.ambient_sensor, "ambient");
  r.comp->PublishModel(m, "double fault");
  r.temps.Set("nut", 26);
  r.temps.Set("bearing", 23);
  r.temps.Set("ambient", 22);
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.SetFault("nut", true);
  r.temps.SetFault("ambient", true);
  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  ASSERT_EQ(lost.axes[0].fallback_model, 0);
  EXPECT_TRUE(lost.axes[0].thermal_used);
  std::vector<double> key{23};
  model::ThermalState no_room{key, std::nan(""), CoolantState::kOff, true};
  EXPECT_NEAR(lost.axes[0].desired_um, model::CorrectionUm(model::Predict(fb, 400, Direction::kForward, no_room)), 1e-9);
  model::ThermalState last_room{key, 22.0, CoolantState::kOff, true};
  EXPECT_GT(std::fabs(lost.axes[0].desired_um - model::CorrectionUm(model::Predict(fb, 400, Direction::kForward, last_room))),
            0.1);  // the room term is gone, not held at the last reading
}

TEST(FallbackModel, WithoutOneTheAxisFallsBackToItsGeometricPart) {
  Rig r;
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  r.comp->PublishModel(m, "no fallback");
  r.comp->RunCycle(r.cnc, r.temps, 0.0);
  r.temps.SetFault("nut", true);
  const auto& lost = r.comp->RunCycle(r.cnc, r.temps, 100.0);
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  EXPECT_FALSE(lost.axes[0].thermal_used);
  EXPECT_EQ(lost.axes[0].fallback_model, -1);
}

TEST(FallbackModel, MoreFallbacksThanTheRuntimeKeepsIsABindErrorNotASilentSkip) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  for (std::size_t f = 0; f <= kMaxFallbackModels; ++f) m->axes.back().fallbacks.push_back(BearingOnlyFallback(0));
  std::vector<AxisInterface> axes(1);
  axes[0].axis = "X";
  try {
    BindModel(m, "model.json", axes, {"ambient", "nut", "bearing"}, {});
    FAIL() << "bound more fallbacks than it keeps states for";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "axes[X].fallbacks") << e.what();
  }
  m->axes.back().fallbacks.pop_back();
  EXPECT_EQ(BindModel(m, "model.json", axes, {"ambient", "nut", "bearing"}, {})->axes[0].fallbacks.size(), kMaxFallbackModels);
}

TEST(FallbackModel, AFallbackWhoseKeyHasNoChannelIsABindErrorNamingIt) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  model::AxisModel f = BearingOnlyFallback(0);
  f.key_sensors = {"motor"};
  m->axes.back().fallbacks.push_back(f);
  std::vector<AxisInterface> axes(1);
  axes[0].axis = "X";
  try {
    BindModel(m, "model.json", axes, {"ambient", "nut", "bearing"}, {});
    FAIL() << "bound a fallback whose key has no channel";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("axes[X].fallbacks[0].key_sensors"), std::string::npos) << what;
    EXPECT_NE(what.find("'motor'"), std::string::npos) << what;
    EXPECT_NE(what.find("--no-fallback-models"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace trueaxis::runtime

namespace trueaxis::runtime {
namespace {

// X with two fallbacks replacing the nut (the bearing with two gains: the fit's re-chosen keys and
// the model's other key) and, between them, one replacing the room sensor.
std::shared_ptr<const model::CompositeModel> ModelWithTwoNutFallbacks(bool state_replaced = true) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  model::AxisModel a = BearingOnlyFallback(0);
  model::AxisModel b = BearingOnlyFallback(0);
  for (auto& d : b.directions) d.thermal = {{CoolantState::kOff, {-0.010}, 0}};
  model::AxisModel no_room = ModelWithRoomFallback()->axes[0].fallbacks[0];
  if (state_replaced) a.replaces = b.replaces = "nut", no_room.replaces = "ambient";
  m->axes.back().fallbacks = {a, no_room, b};
  return m;
}

double DesiredWithoutRoom(const model::AxisModel& a, std::vector<double> keys) {
  model::ThermalState ts{std::span<const double>(keys.data(), keys.size()), std::nan(""), CoolantState::kOff, true};
  return model::CorrectionUm(model::Predict(a, 400, Direction::kForward, ts));
}

// The fallbacks replacing the lost sensor that can run are averaged (AxisModel::replaces): the
// campaign's CV does not rank them the way the working day does. One replacing another sensor is
// not mixed in, and fallbacks of older files (no "replaces") are not averaged.
TEST(FallbackModel, TheFallbacksReplacingTheLostSensorAreAveraged) {
  Rig r;
  const auto m = ModelWithTwoNutFallbacks();
  const auto& fb = m->axes[0].fallbacks;
  r.temps.Set("ambient", 20);
  const auto& lost = r.LoseTheNut(m, "two for the nut");
  ASSERT_EQ(lost.axes[0].fallback_model, 0);
  EXPECT_EQ(lost.axes[0].fallbacks_averaged, 2);
  const double a = Rig::Desired(fb[0], {23}), b = Rig::Desired(fb[2], {23});
  ASSERT_GT(std::fabs(a - b), 1.0);  // the two differ: the mean is told apart from either
  EXPECT_NEAR(lost.axes[0].desired_um, (a + b) / 2, 1e-9);

  // The room sensor lost instead: the fallback replacing it alone.
  r.temps.SetFault("nut", false);
  r.comp->RunCycle(r.cnc, r.temps, 100.01);
  r.temps.SetFault("ambient", true);
  const auto& room = r.comp->RunCycle(r.cnc, r.temps, 200.0);
  ASSERT_EQ(room.axes[0].fallback_model, 1);
  EXPECT_EQ(room.axes[0].fallbacks_averaged, 1);
  EXPECT_NEAR(room.axes[0].desired_um, DesiredWithoutRoom(fb[1], {26, 23}), 1e-9);

  // The nut and the room lost together: the two replacing the nut, both without their room term.
  r.temps.SetFault("nut", true);
  const auto& both = r.comp->RunCycle(r.cnc, r.temps, 300.0);
  ASSERT_EQ(both.axes[0].fallback_model, 0);
  EXPECT_EQ(both.axes[0].fallbacks_averaged, 2);
  EXPECT_NEAR(both.axes[0].desired_um, (DesiredWithoutRoom(fb[0], {23}) + DesiredWithoutRoom(fb[2], {23})) / 2, 1e-9);
}

TEST(FallbackModel, FallbacksThatNameNoReplacedSensorAreNotAveraged) {
  Rig r;
  const auto m = ModelWithTwoNutFallbacks(false);
  const auto& lost = r.LoseTheNut(m, "older file");
  ASSERT_EQ(lost.axes[0].fallback_model, 0);
  EXPECT_EQ(lost.axes[0].fallbacks_averaged, 1);
  EXPECT_NEAR(lost.axes[0].desired_um, Rig::Desired(m->axes[0].fallbacks[0], {23}), 1e-9);
}

// With the hand-over, each averaged fallback starts from the model's last correction, so their mean
// does too; it then decays toward the mean of their own predictions.
TEST(FallbackModel, AveragedFallbacksStartFromTheModelsLastCorrection) {
  const double tau = 600;
  Rig r(tau);
  const auto m = ModelWithTwoNutFallbacks();
  const auto& fb = m->axes[0].fallbacks;
  const auto& lost = r.LoseTheNut(m, "two, hand-over");
  ASSERT_EQ(lost.axes[0].fallbacks_averaged, 2);
  const double model_last = Rig::Desired(m->axes[0], {26, 23});
  EXPECT_NEAR(lost.axes[0].desired_um, model_last, 1e-9);
  const double mean_own = (Rig::Desired(fb[0], {23}) + Rig::Desired(fb[2], {23})) / 2;
  const auto& later = r.comp->RunCycle(r.cnc, r.temps, 100.0 + tau);
  EXPECT_NEAR(later.axes[0].desired_um, mean_own + (model_last - mean_own) * std::exp(-1.0), 1e-9);
}

}  // namespace
}  // namespace trueaxis::runtime
