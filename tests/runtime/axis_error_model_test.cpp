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
  double ErrorUm(double x, Direction d, std::span<const double> t, CoolantState) const override {
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

}  // namespace
}  // namespace trueaxis::runtime
