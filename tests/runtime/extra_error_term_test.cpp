// The additional per-axis error term (StepInputs::extra_error_um, Compensator::SetExtraErrorUm):
// e.g. the camera's spindle Δz on Z (seed 001). It goes through the same output shaper as the
// model: a step ramps at max_step_um per cycle, the axis bound clamps it with an alarm, a
// NaN / empty / expired term changes nothing, and it follows the sign convention.
#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc, testing::MockTemperatures, testing::TestModel;

struct TermRig {
  explicit TermRig(double step_um = 0.5, double bound_um = 40) : cnc({"X", "Z"}), temps({"ambient", "nut", "bearing"}, 20.0) {
    CompensatorOptions o;
    o.shaper.max_step_um = step_um;
    o.shaper.max_correction_um = bound_um;
    comp = Compensator::ForHardware(o, cnc, temps, {});
    cnc.axes[0] = {120, +1, true};
    cnc.axes[1] = {30, -1, true};
  }
  const CycleStatus& Run(int n) {
    const CycleStatus* s = nullptr;
    for (int k = 0; k < n; ++k) {
      const double before = cnc.cnc_value_um[1];
      s = &comp->RunCycle(cnc, temps, t += 0.01);
      max_delta_z = std::max(max_delta_z, std::fabs(cnc.cnc_value_um[1] - before));
      alarms_seen |= s->alarms;
    }
    return *s;
  }
  MockCnc cnc;
  MockTemperatures temps;
  std::unique_ptr<Compensator> comp;
  double t = 0, max_delta_z = 0;
  std::uint32_t alarms_seen = 0;
};

TEST(ExtraErrorTerm, AStepRampsAtTheShaperRateAndSettlesAtItsNegative) {
  TermRig r(2.0);  // above the CNC's 1 µm quantum, so each cycle shows one full step
  r.comp->PublishModel(TestModel(1.0, {"X", "Z"}), "m");
  r.Run(300);  // settled on the model alone
  const double model_only = r.cnc.cnc_value_um[1];
  r.max_delta_z = 0;
  r.comp->SetExtraErrorUm(1, 12.0, 1e9);  // the spindle grew 12 µm: error +12 on Z
  r.Run(1);
  EXPECT_NEAR(r.cnc.cnc_value_um[1] - model_only, -2.0, 1e-9);  // one step, not 12 µm
  r.Run(3);
  EXPECT_NEAR(r.cnc.cnc_value_um[1] - model_only, -8.0, 1e-9);  // still ramping, at 2 µm/cycle
  r.Run(100);
  EXPECT_NEAR(r.cnc.cnc_value_um[1] - model_only, -12.0, 1e-6);  // correction = −(error)
  EXPECT_LE(r.max_delta_z, 2.0 + 1e-9);
  EXPECT_NEAR(r.comp->LastStatus().axes[1].extra_error_um, 12.0, 0);
  EXPECT_NEAR(r.cnc.cnc_value_um[0], r.comp->LastStatus().axes[0].output_um, 1e-9);  // X untouched
  EXPECT_EQ(r.comp->LastStatus().axes[0].extra_error_um, 0.0);
}

TEST(ExtraErrorTerm, WorksWithoutAModelAndIsBoundedWithTheClampedAlarm) {
  TermRig r(2.0, 40);
  r.comp->SetExtraErrorUm(1, 75.0, 1e9);
  const auto& s = r.Run(200);
  EXPECT_NEAR(r.cnc.cnc_value_um[1], -40.0, 1e-9);  // the axis bound
  EXPECT_TRUE(s.alarms & kAlarmCorrectionClamped);
  EXPECT_TRUE(s.axes[1].clamped);
  EXPECT_LE(r.max_delta_z, 2.0 + 1e-9);
  r.comp->SetExtraErrorUm(1, 10.0, 1e9);
  const auto& s2 = r.Run(100);
  EXPECT_NEAR(r.cnc.cnc_value_um[1], -10.0, 1e-9);
  EXPECT_FALSE(s2.alarms & kAlarmCorrectionClamped);
}

TEST(ExtraErrorTerm, NanEmptyAndDisabledChangeNothing) {
  TermRig with, without;
  for (TermRig* r : {&with, &without}) r->comp->PublishModel(TestModel(1.0, {"X", "Z"}), "m");
  with.comp->SetExtraErrorUm(1, std::nan(""), 1e9);
  for (int k = 0; k < 200; ++k) {
    with.Run(1);
    without.Run(1);
    ASSERT_EQ(with.cnc.cnc_value_um[1], without.cnc.cnc_value_um[1]);
    ASSERT_EQ(with.cnc.cnc_value_um[0], without.cnc.cnc_value_um[0]);
  }
  // A term on a disabled axis is not applied.
  with.comp->SetAxisEnabled(1, false);
  with.comp->SetExtraErrorUm(1, 20.0, 1e9);
  with.Run(200);
  EXPECT_EQ(with.cnc.cnc_value_um[1], 0.0);
  // The pure step with an empty span equals one with no term at all (the default).
  EXPECT_TRUE(StepInputs{}.extra_error_um.empty());
}

TEST(ExtraErrorTerm, AnExpiredTermIsDroppedWithTheStaleAlarmNotUsedSilently) {
  TermRig r(1.0);
  r.comp->SetExtraErrorUm(1, 8.0, r.t + 1.0);  // valid for 1 s of loop time
  const auto& s = r.Run(50);                   // 0.5 s
  EXPECT_NEAR(r.cnc.cnc_value_um[1], -8.0, 1e-9);
  EXPECT_FALSE(s.alarms & kAlarmStaleInput);
  const auto& s2 = r.Run(100);  // past its validity: ramps back to the model's (none: 0)
  EXPECT_EQ(r.cnc.cnc_value_um[1], 0.0);
  EXPECT_TRUE(s2.alarms & kAlarmStaleInput);
  EXPECT_LE(r.max_delta_z, 1.0 + 1e-9);
  r.comp->ClearExtraError(1);
  EXPECT_FALSE(r.Run(1).alarms & kAlarmStaleInput);
}

TEST(ExtraErrorTerm, VisionStopRaisesItsAlarmWhileSet) {
  TermRig r;
  EXPECT_FALSE(r.Run(1).alarms & kAlarmVisionStop);
  r.comp->SetVisionStop(true);
  const auto& s = r.Run(1);
  EXPECT_TRUE(s.alarms & kAlarmVisionStop);
  EXPECT_NE(AlarmNames(s.alarms).find("vision_stop"), std::string::npos);
  r.comp->SetVisionStop(false);
  EXPECT_FALSE(r.Run(1).alarms & kAlarmVisionStop);
}

}  // namespace
}  // namespace trueaxis::runtime
