// The direction model of the cycle (docs/runtime.md step 4): which of the forward and reverse
// models an axis is compensated with after a move, also after a move too short for the loop to
// see the CNC's `moving` flag (a laser cycle's overrun of a few mm at rapid feed).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fakes.hpp"

namespace trueaxis::runtime {
namespace {
using testing::OneAxisRig;
using testing::TestModel;

struct DirectionRig : OneAxisRig {
  DirectionRig() { comp->PublishModel(TestModel(1.0, {"X"}), "test"); }
  const CycleStatus& Sample(double position_mm, int servo_direction, bool moving, int cycles = 1,
                            int programmed_direction = 0) {
    cnc.axes[0] = {position_mm, servo_direction, moving};
    cnc.axes[0].programmed_direction = programmed_direction;
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

// The CNC's programmed direction wins: a whole overrun done between two reads (the axis stands on
// the target again, no position change, the servo register still +), out 5 mm and back 3 mm (the
// position says forward from the turning point), and standing with the compensation's nudges.
TEST(Direction, TheProgrammedDirectionFromTheLinkWins) {
  DirectionRig r;
  r.ForwardAt300();
  r.Sample(300, +1, false, 1, -1);  // 300 → 305 → 300 between two reads: only the program tells
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kReverse);
  r.Sample(300, +1, false, 2, +1);
  ASSERT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kForward);
  r.Sample(302, -1, false, 1, -1);  // out to 305 and back to 302 between two reads
  EXPECT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kReverse);
  for (int i = 0; i < 20; ++i) {  // standing: nudges of the position and a flickering servo register
    r.Sample(302 + (i % 2 ? 0.003 : -0.003), i % 2 ? +1 : -1, false, 1, -1);
    ASSERT_EQ(r.comp->LastStatus().axes[0].direction, Direction::kReverse) << "sample " << i;
  }
  // It also wins over a servo direction the runtime takes at any report.
  OneAxisRig any;
  CompensatorOptions o;
  o.direction_only_while_moving = false;
  any.comp = Compensator::ForHardware(o, any.cnc, any.temps, {});
  any.comp->PublishModel(TestModel(1.0, {"X"}), "test");
  any.cnc.axes[0] = {250, +1, false};
  any.cnc.axes[0].programmed_direction = -1;
  EXPECT_EQ(any.comp->RunCycle(any.cnc, any.temps, 0.01).axes[0].direction, Direction::kReverse);
}

// A reversal the loop saw only as its sum: a creep back from the turning point in steps below the
// threshold (no `moving` flag), which two successive reads never show, still switches the model
// once it has gone back by more than direction_min_move_um.
TEST(Direction, AReversalCountsFromTheTurningPoint) {
  DirectionRig r;
  r.ForwardAt300();
  r.Sample(300.004, 0, false);  // 4 µm farther forward: the turning point moves with it
  for (int k = 1; k <= 5; ++k) {  // back by 0.8 µm per read: 0.8, 1.6, 2.4, ... µm from the turning point
    r.Sample(300.004 - 0.0008 * k, 0, false);
    EXPECT_EQ(r.comp->LastStatus().axes[0].direction, k <= 2 ? Direction::kForward : Direction::kReverse)
        << 0.8 * k << " µm back";
  }
}

// A laser cycle as the CNC runs it (ISO 230-2 up and down): from below the first target by the
// overrun, every target going up with a dwell, past the last by the overrun and back onto it,
// every target coming down, below the first by the overrun and back. The loop reads every 0.1 s;
// the 5 mm overrun at 2000 mm/min takes 0.15 s each way, so the loop sees one or two reads of each
// leg, at a phase that varies from run to run.
//
// The CNC reports its commanded position, `moving` and the servo direction while the program moves
// the axis, and a servo direction register that, standing, holds where the MOTOR last moved — the
// compensation's own moves included (a CNC's moving-direction signal when the correction goes
// through the servo). It applies each new correction as a ramp (60 µm/s). When the loop's one read
// of an overrun's return leg switches the model, the reversal value it writes is still being ramped
// in when the axis arrives on the target, so the register shows the ramp's direction, not the
// approach. At the end of every dwell the model in force must be the approach's direction.
TEST(Direction, ALaserCyclesShortOverrunsSwitchTheModelAtEveryPhase) {
  struct Move {
    double from_mm, to_mm, start_s, end_s;
    bool record;  // a dwell for a reading follows
    int Dir() const { return to_mm > from_mm ? +1 : -1; }
  };
  const double feed_mm_s = 2000.0 / 60, overrun_mm = 5, dwell_s = 2, period_s = 0.1, ramp_um_s = 60;
  ASSERT_LT(overrun_mm / feed_mm_s, 2 * period_s);  // the loop sees at most two reads of an overrun leg
  std::vector<double> targets;
  for (double x = 20; x <= 520; x += 100) targets.push_back(x);
  std::vector<Move> moves;
  double at_mm = targets.front() - overrun_mm, t_s = 1;
  const auto go = [&](double to_mm, bool record) {
    const double end_s = t_s + std::fabs(to_mm - at_mm) / feed_mm_s;
    moves.push_back({at_mm, to_mm, t_s, end_s, record});
    at_mm = to_mm;
    t_s = end_s + (record ? dwell_s : 0);
  };
  for (int run = 0; run < 2; ++run) {
    for (double x : targets) go(x, true);
    go(targets.back() + overrun_mm, false);
    for (auto it = targets.rbegin(); it != targets.rend(); ++it) go(*it, true);
    go(targets.front() - overrun_mm, false);
  }
  int dwells = 0, wrong_runs = 0;
  for (int phase = 0; phase < 10; ++phase) {
    DirectionRig r;
    r.comp->PublishModel(TestModel(3.0, {"X"}), "test");  // a reversal value of 18 µm
    r.Sample(targets.front() - overrun_mm, +1, false, 3);
    double applied_um = r.cnc.cnc_value_um[0], ramp_to_um = applied_um, ramp_end_s = 0;
    int ramp_dir = 0, motor_dir = +1, wrong = 0;
    for (double prev = 0.9, t = prev + 0.01 * phase; t < moves.back().end_s + 1; prev = t, t += period_s) {
      // The program at t, and the last programmed motion within (prev, t].
      double x_mm = moves.front().from_mm, program_end_s = -1;
      int program_dir = 0;
      bool moving = false;
      for (const Move& mv : moves) {
        if (mv.start_s >= t) break;
        x_mm = t >= mv.end_s ? mv.to_mm : mv.from_mm + mv.Dir() * feed_mm_s * (t - mv.start_s);
        moving = t < mv.end_s;
        if (mv.end_s > prev) program_end_s = std::min(mv.end_s, t), program_dir = mv.Dir();
      }
      // The register: whichever of the program and the correction's ramp moved the motor last.
      const double ramp_in_s = ramp_end_s > prev ? std::min(ramp_end_s, t) : -1;
      if (moving) motor_dir = program_dir;
      else if (ramp_in_s > program_end_s) motor_dir = ramp_dir;
      else if (program_end_s > 0) motor_dir = program_dir;
      r.cnc.axes[0] = {x_mm, motor_dir, moving};
      r.t = t;
      const CycleStatus& s = r.comp->RunCycle(r.cnc, r.temps, t);
      // The ramp towards the correction just written, from where it has got to.
      applied_um = ramp_end_s > t ? ramp_to_um - ramp_dir * ramp_um_s * (ramp_end_s - t) : ramp_to_um;
      if (r.cnc.cnc_value_um[0] != ramp_to_um) {
        ramp_to_um = r.cnc.cnc_value_um[0];
        ramp_dir = ramp_to_um > applied_um ? +1 : -1;
        ramp_end_s = t + std::fabs(ramp_to_um - applied_um) / ramp_um_s;
      }
      for (const Move& mv : moves) {
        if (!mv.record || t < mv.end_s || t >= mv.end_s + dwell_s || t + period_s < mv.end_s + dwell_s) continue;
        ++dwells;  // the dwell's last read
        const Direction approach = mv.Dir() > 0 ? Direction::kForward : Direction::kReverse;
        if (s.axes[0].direction != approach) ++wrong;
        EXPECT_EQ(s.axes[0].direction, approach) << "phase " << phase << ": target " << mv.to_mm << " approached "
                                                 << (mv.Dir() > 0 ? "forward" : "in reverse");
      }
    }
    wrong_runs += wrong > 0;
  }
  EXPECT_EQ(wrong_runs, 0) << "of 10 runs";
  EXPECT_EQ(dwells, 10 * 2 * 2 * static_cast<int>(targets.size()));  // every reading was checked
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
