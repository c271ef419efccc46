// A compensator for composite models only (ModelKinds::kCompositeOnly, what an installation without
// thermal_channels builds) holds no state for models behind the generic interface, refuses such a
// model, and steps a composite model exactly as a compensator that takes both kinds.
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;

class ConstantErrorModel : public model::AxisErrorModel {
 public:
  const std::string& Axis() const override { return axis_; }
  const std::vector<std::string>& Sensors() const override { return sensors_; }
  std::string Describe() const override { return "constant"; }
  double ErrorUm(double, Direction, std::span<const double>, CoolantState, const model::AxisModelDynamics&) const override {
    return 5.0;
  }

 private:
  std::string axis_ = "X";
  std::vector<std::string> sensors_ = {"nut"};
};

std::unique_ptr<Compensator> Make(MockCnc& cnc, MockTemperatures& temps, ModelKinds kinds) {
  CompensatorOptions o;
  o.shaper.max_step_um = 0.5;
  return Compensator::ForHardware(o, cnc, temps, {}, kinds);
}

TEST(ModelKinds, CompositeOnlyHoldsNoGenericModelState) {
  MockCnc cnc({"X", "Y"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  EXPECT_EQ(Make(cnc, temps, ModelKinds::kCompositeAndGeneric)->state().dynamics.generic.size(), 2u);
  EXPECT_TRUE(Make(cnc, temps, ModelKinds::kCompositeOnly)->state().dynamics.generic.empty());
}

TEST(ModelKinds, CompositeOnlyRefusesAGenericModel) {
  MockCnc cnc({"X", "Y"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  auto comp = Make(cnc, temps, ModelKinds::kCompositeOnly);
  EXPECT_THROW(comp->PublishAxisModels({std::make_shared<ConstantErrorModel>()}, "constant"), std::logic_error);
  // The composite still binds, and the refused model was never published: no model yet.
  EXPECT_TRUE(comp->RunCycle(cnc, temps, 0.01).alarms & kAlarmNoModel);
  comp->PublishModel(testing::TestModel(), "test");
  EXPECT_FALSE(comp->RunCycle(cnc, temps, 0.02).alarms & kAlarmNoModel);
}

TEST(ModelKinds, ACompositeModelStepsTheSameEitherWay) {
  MockCnc cnc({"X", "Y"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  auto both = Make(cnc, temps, ModelKinds::kCompositeAndGeneric);
  auto composite = Make(cnc, temps, ModelKinds::kCompositeOnly);
  both->PublishModel(testing::TestModel(), "test");
  composite->PublishModel(testing::TestModel(), "test");
  double t = 0;
  for (int i = 0; i < 300; ++i) {
    cnc.axes[0] = {100.0 + i, i % 50 < 25 ? 1 : -1, true};  // moving, reversing
    if (i == 150) temps.SetFault("nut", true);              // the key sensor lost: held, then fallback
    t += 0.05;
    const CycleStatus& a = both->RunCycle(cnc, temps, t);
    const CycleStatus& b = composite->RunCycle(cnc, temps, t);
    ASSERT_EQ(a.alarms, b.alarms) << "cycle " << i;
    for (std::size_t k = 0; k < 2; ++k) {
      ASSERT_EQ(a.axes[k].desired_um, b.axes[k].desired_um) << "cycle " << i << " axis " << k;
      ASSERT_EQ(a.axes[k].output_um, b.axes[k].output_um) << "cycle " << i << " axis " << k;
    }
  }
  EXPECT_NE(both->LastStatus().axes[0].output_um, 0.0);  // the model drove the axis
}

}  // namespace
}  // namespace trueaxis::runtime
