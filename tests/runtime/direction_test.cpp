// The direction model of the cycle (docs/runtime.md step 4): which of the forward and reverse
// models an axis is compensated with after a move, also after a move too short for the loop to
// see the CNC's `moving` flag (a laser cycle's overrun of a few mm at rapid feed).
#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"

namespace trueaxis::runtime {
namespace {
using testing::OneAxisRig;
using testing::TestModel;

struct DirectionRig : OneAxisRig {
  DirectionRig() { comp->PublishModel(TestModel(1.0, {"X"}), "test"); }
  const CycleStatus& Sample(double position_mm, int servo_direction, bool moving, int cycles = 1) {
    cnc.axes[0] = {position_mm, servo_direction, moving};
    const CycleStatus* s = nullptr;
    for (int i = 0; i < cycles; ++i) {
      t += 0.01;
      s = &comp->RunCycle(cnc, temps, t);
    }
    return *s;
  }
  // Approached 300 mm forward, then the reading's dwell: the forward model in force.
  void ForwardAt300() {
    Sample(290, +1, true, 3);
    Sample(300, +1, false, 5);
    ASSERT_EQ(comp->LastStatus().axes[0].direction, Direction::kForward);
  }
  double t = 0;
};

// The laser cycle's reversal: forward past the target by the 5 mm overrun, then back onto it. The
// loop sees each move only in the sample after it ended (the axis already stopped, `moving` never
// set): the terminal's direction register says where it last moved, and that model must be used.
TEST(Direction, ShortReversalSeenOnlyAfterItEndedSwitchesTheModel) {
  DirectionRig r;
  r.ForwardAt300();
  r.Sample(305, +1, false, 3);  // the overrun, seen only standing at its end
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kForward);
  const auto& s = r.Sample(300, -1, false, 3);  // back onto the target: a 5 mm reverse move
  EXPECT_EQ(s.axes[0].direction, Direction::kReverse);
  const double reverse_um = s.axes[0].desired_um;
  r.Sample(300, -1, true, 1);  // the same model as if the loop had seen the move
  EXPECT_DOUBLE_EQ(r.comp->LastStatus().axes[0].desired_um, reverse_um);
}

// A CNC that reports no direction (0): the direction of the position change decides.
TEST(Direction, WithoutADirectionRegisterThePositionChangeDecides) {
  DirectionRig r;
  r.ForwardAt300();
  r.Sample(305, 0, false, 2);
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kForward);
  r.Sample(300, 0, false, 2);
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kReverse);
  r.Sample(300.01, 0, false, 2);  // 10 µm forward, one sample: a move
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kForward);
}

// The direction the CNC reports wins over the sign of the change: out 5 mm and back 3 mm between
// two samples ends with a reverse approach.
TEST(Direction, TheCncsDirectionWinsOverTheNetPositionChange) {
  DirectionRig r;
  r.ForwardAt300();
  r.Sample(302, -1, false, 2);
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kReverse);
}

// Standing still, position noise of an encoder count or two and the CNC's direction register
// flickering with the compensation's own µm nudges never flip the model (no limit cycle).
TEST(Direction, NoiseAndStandstillNudgesDoNotFlipTheModel) {
  DirectionRig r;
  r.ForwardAt300();
  for (int i = 0; i < 20; ++i) {
    r.Sample(300 + (i % 2 ? 0.0005 : -0.0005), i % 2 ? +1 : -1, false);
    ASSERT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kForward) << "sample " << i;
  }
}

// A CNC whose reported position includes the compensation it applies (here one cycle late): the
// correction ramping by its rate limit moves the position by as much, and the CNC reports the
// nudges as a direction; that is no move of the axis.
TEST(Direction, TheCompensationsOwnRampIsNoMove) {
  OneAxisRig r;
  CompensatorOptions o;
  o.shaper.max_step_um = 3;  // beyond the noise threshold per cycle
  o.shaper.max_correction_um = 500;
  r.comp = Compensator::ForHardware(o, r.cnc, r.temps, {});
  r.comp->PublishModel(TestModel(1.0, {"X"}), "test");
  r.temps.Set("nut", 30);  // a warm nut: the correction ramps −, the axis is nudged −
  double t = 0;
  r.cnc.axes[0] = {300, +1, true};
  r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
  r.cnc.axes[0].moving = false;
  double applied_um = 0;  // what the CNC applies: the output of the cycle before
  for (int i = 0; i < 40; ++i) {
    r.cnc.axes[0].position_mm = 300 + applied_um / 1000;
    r.cnc.axes[0].servo_direction = -1;
    applied_um = r.comp->LastStatus().axes[0].output_um;
    const auto& s = r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
    ASSERT_EQ(s.axes[0].direction, Direction::kForward) << "cycle " << i << ", applied " << applied_um << " µm";
  }
  ASSERT_LT(r.comp->LastStatus().axes[0].output_um, -20);  // the ramp did run
}

// The switch goes through the output shaper: the reversal value is ramped in, never jumped.
TEST(Direction, TheSwitchIsRateLimited) {
  OneAxisRig r;
  CompensatorOptions o;
  o.shaper.max_step_um = 0.5;
  o.shaper.max_correction_um = 500;
  r.comp = Compensator::ForHardware(o, r.cnc, r.temps, {});
  r.comp->PublishModel(TestModel(1.0, {"X"}), "test");
  double t = 0;
  r.cnc.axes[0] = {300, +1, true};
  for (int i = 0; i < 200; ++i) r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
  r.cnc.axes[0] = {305, +1, false};
  r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
  r.cnc.axes[0] = {300, -1, false};
  double last = r.comp->LastStatus().axes[0].output_um;
  const auto& first = r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
  ASSERT_EQ(first.axes[0].direction, Direction::kReverse);
  const double target = first.axes[0].desired_um;
  ASSERT_GT(std::fabs(target - last), 3);  // the reversal value is worth ramping
  for (int i = 0; i < 200; ++i) {
    const auto& s = r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
    EXPECT_LE(std::fabs(s.axes[0].output_um - last), 1.0 + 1e-9) << "cycle " << i;  // max(q, max_step)
    last = s.axes[0].output_um;
  }
  EXPECT_NEAR(last, target, 0.75 + 1e-9);
}

}  // namespace
}  // namespace trueaxis::runtime
