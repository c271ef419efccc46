// The compensator binds models behind model::AxisErrorModel (PublishAxisModels): sensors mapped to
// channels by name, correction = −error through the same limiter, a lost sensor ramps to zero.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;

// error = a·(T_nut − 20) + b·position, reverse adds 3 µm.
class LinearTestModel : public model::AxisErrorModel {
 public:
  explicit LinearTestModel(std::string axis) : axis_(std::move(axis)) {}
  const std::string& Axis() const override { return axis_; }
  const std::vector<std::string>& Sensors() const override { return sensors_; }
  std::string Describe() const override { return "linear test model"; }
  double ErrorUm(double x, Direction d, std::span<const double> t, CoolantState,
                 const model::AxisModelDynamics&) const override {
    return 2.0 * (t[0] - 20.0) + 0.01 * x + (d == Direction::kReverse ? 3.0 : 0.0);
  }

 private:
  std::string axis_;
  std::vector<std::string> sensors_ = {"nut"};
};

struct Rig {
  Rig() : cnc({"X", "Y"}), temps({"ambient", "nut", "bearing"}, 25.0) {
    CompensatorOptions o;
    o.shaper.max_step_um = 0.5;
    o.sensor.hold_last_good_s = 1.0;
    comp = Compensator::ForHardware(o, cnc, temps, {});
    cnc.axes[0] = {300, 1, true};
  }
  const CycleStatus& Run(int cycles) {
    const CycleStatus* s = nullptr;
    for (int i = 0; i < cycles; ++i) s = &comp->RunCycle(cnc, temps, t += 0.01);
    return *s;
  }
  MockCnc cnc;
  MockTemperatures temps;
  std::unique_ptr<Compensator> comp;
  double t = 0;
};

TEST(AxisErrorModel, CorrectionIsMinusTheModelsErrorThroughTheLimiter) {
  Rig r;
  r.comp->PublishAxisModels({std::make_shared<LinearTestModel>("X")}, "test");
  const auto& s = r.Run(200);
  const double error = 2.0 * (25 - 20) + 0.01 * 300;  // 13 µm
  EXPECT_DOUBLE_EQ(s.axes[0].desired_um, -error);
  EXPECT_DOUBLE_EQ(s.axes[0].output_um, -error);  // reached at 0.5 µm per cycle
  EXPECT_TRUE(s.alarms & kAlarmNoModelForAxis);  // Y has none
  r.cnc.axes[0] = {300, -1, true};
  EXPECT_DOUBLE_EQ(r.Run(1).axes[0].desired_um, -(error + 3.0));  // the reverse model
}

TEST(AxisErrorModel, ALostSensorRampsTheAxisToZero) {
  Rig r;
  r.comp->PublishAxisModels({std::make_shared<LinearTestModel>("X")}, "test");
  r.Run(200);
  r.temps.SetFault("nut", true);
  const auto& held = r.Run(10);  // within hold_last_good_s: last good value
  EXPECT_TRUE(held.alarms & kAlarmSensorHeld);
  EXPECT_NEAR(held.axes[0].output_um, -13.0, 1e-9);
  const auto& lost = r.Run(200);
  EXPECT_TRUE(lost.alarms & kAlarmSensorFallback);
  EXPECT_EQ(lost.axes[0].output_um, 0.0);
}

TEST(AxisErrorModel, BindingErrorsNameTheSensorAndTheAxis) {
  Rig r;
  class Unmapped : public LinearTestModel {
   public:
    Unmapped() : LinearTestModel("X") {}
    const std::vector<std::string>& Sensors() const override { return s_; }
    std::vector<std::string> s_ = {"spindle"};
  };
  try {
    r.comp->PublishAxisModels({std::make_shared<Unmapped>()}, "m.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("spindle"), std::string::npos) << e.what();
  }
  EXPECT_THROW(r.comp->PublishAxisModels({std::make_shared<LinearTestModel>("Q")}, "m.json"), InputError);
  EXPECT_THROW(r.comp->PublishAxisModels({std::make_shared<LinearTestModel>("X"), std::make_shared<LinearTestModel>("X")}, "m.json"),
               InputError);
}

// A model with dynamics: its error is the nut temperature's trend (°C/h) in µm, over a 10 s window.
class TrendTestModel : public LinearTestModel {
 public:
  TrendTestModel() : LinearTestModel("X") {}
  double ErrorUm(double, Direction, std::span<const double>, CoolantState,
                 const model::AxisModelDynamics& d) const override {
    return d.trend.Samples() >= 3 ? d.trend.SlopePerH() : 0.0;
  }
  bool HasDynamics() const override { return true; }
  void Advance(model::AxisModelDynamics& d, double now_s, std::span<const double> t) const override {
    ++advances;
    d.trend.Push(now_s, t[0]);
  }
  void ResetDynamics(model::AxisModelDynamics& d) const override {
    ++resets;
    d.trend.Configure(10.0);
  }
  mutable int advances = 0, resets = 0;
};

TEST(AxisErrorModel, AModelsDynamicsAreAdvancedEveryCycleAndRestartedAfterALostSensor) {
  Rig r;
  auto m = std::make_shared<TrendTestModel>();
  r.comp->PublishAxisModels({m}, "test");
  // The nut warms at 0.001 °C per 10 ms cycle = 360 °C/h (a test ramp, inside the rate limit).
  double nut = 25.0;
  const CycleStatus* s = nullptr;
  for (int i = 0; i < 1500; ++i) {
    r.temps.Set("nut", nut += 0.001);
    s = &r.comp->RunCycle(r.cnc, r.temps, r.t += 0.01);
  }
  EXPECT_EQ(m->resets, 1);  // at the model's first cycle
  EXPECT_EQ(m->advances, 1500);
  EXPECT_NEAR(s->axes[0].desired_um, -360.0, 1.0);  // correction = −error = −trend
  // The sensor is lost: the axis ramps to zero and the model's state restarts when it returns.
  r.temps.SetFault("nut", true);
  r.Run(300);
  const int advances_before = m->advances;
  r.temps.SetFault("nut", false);
  r.Run(5);
  EXPECT_GE(m->resets, 2);
  EXPECT_GT(m->advances, advances_before);
}

}  // namespace
}  // namespace trueaxis::runtime
